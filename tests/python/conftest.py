"""Shared fixtures of the Python package's tests (tests/python/, CTest label python).

The package comes from PYTHONPATH (build/python in the main suite); TESSERA_RENDER_EXE names
the tessera-render executable the images are compared with.
"""
import os
import subprocess

import numpy as np
import pytest

import tessera

HERE = os.path.dirname(os.path.abspath(__file__))

# One small scene: every image test renders it (a few ms), through tessera.render and the CLI
SCENE = """\
tessera: {{output_dir: out, threads: 2}}
volume: {{file: {file}, dims: [{nx}, {ny}, {nz}], dtype: {dtype}, spacing: [1.0, 1.5, 2.0], origin: [-3, 0, 1]}}
renders:
  - name: main
    image: {{width: 32, height: 24, spp: 4}}
    camera: {{position: {{orbit: {{azimuth: 30, elevation: 20, distance: fit}}}}, look_at: center, up: [0, 0, 1], fov: 30}}
    transfer_function: {{range: auto, density_scale: 2.0, opacity: [[0, 0], [1, 1]], diffuse: viridis}}
    lights: [{{type: sphere, position: {{orbit: {{azimuth: -40, elevation: 50, distance: 3}}}}, radius: {{relative: 0.2}}, color: [1, 1, 1], intensity: 20}}]
    integrator: {{seed: 7, tile: 8}}
    output: {{file: main, formats: [exr]}}
  - name: second
    image: {{width: 16, height: 16, spp: 2}}
    camera: {{position: {{orbit: {{azimuth: 120, elevation: -10, distance: fit}}}}, look_at: center, up: [0, 0, 1], fov: 40}}
    transfer_function: {{range: auto, density_scale: 1.0, opacity: [[0, 0], [1, 0.5]], diffuse: magma}}
    output: {{file: second, formats: [exr]}}
"""


def field(nx=20, ny=16, nz=12, dtype=np.float32):
    """A smooth C-ordered (nz, ny, nx) field with values spanning ``dtype``'s useful range."""
    z, y, x = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    f = np.sin(x / 3.0) * np.cos(y / 4.0) + z / nz  # about [-1, 2]
    if np.issubdtype(dtype, np.integer):
        f = (f + 1.0) / 3.0 * (200 if dtype == np.uint8 else 20000)
    return np.ascontiguousarray(f.astype(dtype))


def write_scene(folder, data_czyx, name="scene.yaml"):
    """Writes data (C-ordered nz, ny, nx) as a raw file and the scene naming it; returns the path."""
    nz, ny, nx = data_czyx.shape
    np.ascontiguousarray(data_czyx).astype(data_czyx.dtype.newbyteorder("<")).tofile(os.path.join(folder, "vol.raw"))
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write(SCENE.format(file="vol.raw", nx=nx, ny=ny, nz=nz, dtype=data_czyx.dtype.name))
    return path


def cli_image(scene, render="main", tmp=None, step=0):
    """tessera-render's EXR of ``render`` (at ``step``: --step) as float32 (H, W, 4)."""
    exe = os.environ.get("TESSERA_RENDER_EXE")
    if not exe:
        pytest.skip("TESSERA_RENDER_EXE is not set")
    out = os.path.join(tmp or os.path.dirname(scene), f"cli_{render}_{step}.exr")
    subprocess.run([exe, scene, "--render", render, "-o", out, "--quiet", "--step", str(step)],
                   check=True, timeout=120)
    return tessera._tessera._read_exr(out)


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))
