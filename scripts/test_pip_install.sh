#!/usr/bin/env bash
# The Python package as a user installs it (docs/python.md): a clean `git clone` of this
# commit, a fresh venv, `pip install .`, then `import tessera` and tessera.render of a
# transposed numpy view, which must equal tessera-render's EXR bit for bit.
# Needs the Debian packages (scripts/setup.sh) and build/bin/tessera-render (scripts/test.sh
# builds both; TESSERA_RENDER_EXE overrides the path). Rebuilds the libraries inside pip, so
# it is not part of the CTest suite; .ci/run calls it after the tests. Uncommitted changes are
# not in the clone.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
exe="${TESSERA_RENDER_EXE:-$repo/build/bin/tessera-render}"
[ -x "$exe" ] || { echo "test_pip_install: $exe not found (run scripts/test.sh first)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Clean clone of this commit, fresh venv, pip install .
git clone -q --no-checkout "$repo" "$tmp/src"
git -C "$tmp/src" checkout -q "$(git rev-parse HEAD)"
python3 -m venv "$tmp/venv"
"$tmp/venv/bin/pip" install -q --upgrade pip >/dev/null
start=$SECONDS
"$tmp/venv/bin/pip" install -q "$tmp/src"
echo "test_pip_install: pip install . took $((SECONDS - start)) s"

# import, render a transposed view, compare with the CLI (from outside the source tree)
cd "$tmp"
"$tmp/venv/bin/python" - "$exe" <<'PY'
import subprocess, sys
import numpy as np
import tessera

exe = sys.argv[1]
nz, ny, nx = 10, 14, 18
z, y, x = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
vol = (np.sin(x / 3.0) * np.cos(y / 4.0) + z / nz).astype(np.float32)  # C order (nz, ny, nx)
vol.tofile("vol.raw")
open("scene.yaml", "w").write(f"""\
volume: {{file: vol.raw, dims: [{nx}, {ny}, {nz}], dtype: float32, spacing: [1, 1.5, 2]}}
renders:
  - name: view
    image: {{width: 40, height: 30, spp: 4}}
    camera: {{position: {{orbit: {{azimuth: 30, elevation: 20, distance: fit}}}}, up: [0, 0, 1], fov: 30}}
    transfer_function: {{range: auto, density_scale: 2.0, opacity: [[0, 0], [1, 1]], diffuse: viridis}}
""")
subprocess.run([exe, "scene.yaml", "-o", "cli.exr", "--quiet"], check=True)
image = tessera.render(vol.T, "scene.yaml")
reference = tessera._tessera._read_exr("cli.exr")
same = image.shape == reference.shape and np.array_equal(image.view(np.uint32), reference.view(np.uint32))
print(f"test_pip_install: import tessera from {tessera.__file__}")
print(f"test_pip_install: tessera.render(vol.T) {'==' if same else '!='} tessera-render, {image.shape}")
print("1 passed, 0 failed" if same else "0 passed, 1 failed")
sys.exit(0 if same else 1)
PY
