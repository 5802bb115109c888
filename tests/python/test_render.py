"""tessera.render: in place (zero copy), every dtype and layout, bit-identical to tessera-render."""
import threading
import time
import tracemalloc

import numpy as np
import pytest

import tessera
from conftest import cli_image, field, same_bits, write_scene


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """The float32 field, its scene file and tessera-render's image of it."""
    tmp = tmp_path_factory.mktemp("render")
    data = field()
    path = write_scene(str(tmp), data)
    return data, path, cli_image(path)


def test_transposed_view_is_bit_identical_to_the_cli(scene):
    data, path, ref = scene
    img = tessera.render(data.T, path)
    assert img.shape == (24, 32, 4) and img.dtype == np.float32
    assert img[..., 3].max() > 0.1  # the data is in view
    assert same_bits(img, ref)


def test_step_draws_that_steps_random_numbers_as_the_cli(scene, tmp_path):
    data, path, ref = scene
    img = tessera.render(data.T, path, step=12)
    assert same_bits(img, cli_image(path, tmp=str(tmp_path), step=12))
    assert not same_bits(img, ref)  # step 0's noise differs
    with pytest.raises(TypeError, match="step"):
        tessera.render(data.T, path, step=1.5)


def test_renders_in_place_without_copying(scene):
    data, path, _ = scene
    big = field(64, 64, 64, np.float64)  # 2 MiB: a copy would show in tracemalloc's peak
    view = big.T
    tracemalloc.start()
    try:
        tessera.render(view, path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert tessera._render._last_field_address == big.__array_interface__["data"][0]
    assert peak < big.nbytes // 8, f"peak {peak} bytes while rendering a {big.nbytes}-byte field"


@pytest.mark.parametrize("layout", ["fortran", "sliced", "negative", "strided_component", "read_only"])
def test_layouts_render_the_same_vertices(scene, tmp_path, layout):
    """The same logical field held in other layouts gives the same bits, read in place."""
    data, path, ref = scene
    xyz = data.T  # (nx, ny, nz) view: vertex (i, j, k)
    if layout == "fortran":
        arr = np.asfortranarray(xyz)  # a Fortran-ordered copy made by the test, then viewed as is
        held = arr
    elif layout == "sliced":
        held = np.zeros((data.shape[2] + 3, data.shape[1] + 2, data.shape[0] + 5), np.float32)
        held[2:-1, 1:-1, 3:-2] = xyz
        arr = held[2:-1, 1:-1, 3:-2]
    elif layout == "negative":
        held = np.ascontiguousarray(xyz[::-1, :, ::-1])
        arr = held[::-1, :, ::-1]
    elif layout == "read_only":  # e.g. np.frombuffer over bytes
        held = np.frombuffer(data.tobytes(), np.float32).reshape(data.shape)
        assert not held.flags.writeable
        arr = held.T
    else:  # one component of a (nx, ny, nz, 3) array
        held = np.zeros(xyz.shape + (3,), np.float32)
        held[..., 1] = xyz
        arr = held[..., 1]
    img = tessera.render(arr, path)
    assert tessera._render._last_field_address == arr.__array_interface__["data"][0]
    assert same_bits(img, ref)


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.uint16, np.float32, np.float64])
def test_every_dtype_is_bit_identical_to_the_cli(tmp_path, dtype):
    data = field(dtype=dtype)
    path = write_scene(str(tmp_path), data)
    img = tessera.render(data.T, path)
    assert tessera._render._last_field_address == data.__array_interface__["data"][0]
    assert same_bits(img, cli_image(path))


def test_render_by_name_and_index(scene, tmp_path):
    data, path, _ = scene
    second = cli_image(path, "second", str(tmp_path))
    assert same_bits(tessera.render(data.T, path, render="second"), second)
    assert same_bits(tessera.render(data.T, path, render=1), second)
    with pytest.raises(ValueError, match=r"render 'nope': no such render .*\(renders: main, second\)"):
        tessera.render(data.T, path, render="nope")
    with pytest.raises(ValueError, match=r"has 2 render"):
        tessera.render(data.T, path, render=5)


def test_dict_config_equals_the_file(scene):
    data, path, ref = scene
    cfg = {
        "tessera": {"threads": 1},
        "renders": [{
            "name": "main",
            "image": {"width": 32, "height": 24, "spp": 4},
            "camera": {"position": {"orbit": {"azimuth": 30, "elevation": 20, "distance": "fit"}},
                       "look_at": "center", "up": [0, 0, 1], "fov": 30},
            "transfer_function": {"range": "auto", "density_scale": 2.0, "opacity": [[0, 0], [1, 1]],
                                  "diffuse": "viridis"},
            "lights": [{"type": "sphere", "position": {"orbit": {"azimuth": -40, "elevation": 50, "distance": 3}},
                        "radius": {"relative": 0.2}, "color": [1, 1, 1], "intensity": np.float64(20)}],
            "integrator": {"seed": 7, "tile": 8},
        }],
    }
    img = tessera.render(data.T, cfg, spacing=(1.0, 1.5, 2.0), origin=np.array([-3, 0, 1]))
    assert same_bits(img, ref)  # threads: 1 against the file's 2: the same bits
    # Without the volume: block's geometry the data is framed differently
    assert not same_bits(tessera.render(data.T, cfg), ref)


def test_config_file_errors_carry_position_and_key_path(scene, tmp_path):
    data, _, _ = scene
    bad = tmp_path / "bad.yaml"
    bad.write_text("renders:\n  - name: a\n    camera: {position: [40, 30, 30], fov: 270}\n    transfer_function: {opacity: [[0, 0], [1, 1]]}\n")
    with pytest.raises(tessera.ConfigError) as e:
        tessera.render(data.T, str(bad))
    assert isinstance(e.value, ValueError)
    assert e.value.key_path == "renders[0].camera.fov"
    assert e.value.line == 3 and e.value.column > 0 and e.value.file == str(bad)
    assert str(e.value).startswith(f"{bad}:3:") and "renders[0].camera.fov" in str(e.value)
    with pytest.raises(tessera.ConfigError, match="does not exist"):
        tessera.render(data.T, str(tmp_path / "missing.yaml"))


def test_dict_errors_name_the_key(scene):
    data, _, _ = scene
    cfg = {"renders": [{"name": "a", "transfer_function": {"opacity": [[0, 0], [1, 1]]},
                        "camera": {"position": [40, 30, 30], "fov": 30, "zoom": 2}}]}
    with pytest.raises(tessera.ConfigError) as e:
        tessera.render(data.T, cfg)
    assert e.value.key_path == "renders[0].camera.zoom"
    assert str(e.value).startswith("config dict: renders[0].camera.zoom: ")
    with pytest.raises(tessera.ConfigError, match=r"config dict: renders\[0\]\.image\.spp"):
        tessera.render(data.T, {"renders": [{"name": "a", "image": {"spp": -1}, "camera": {"position": [40, 30, 30]},
                                             "transfer_function": {"opacity": [[0, 0], [1, 1]]}}]})
    with pytest.raises(tessera.ConfigError, match=r"^config dict: renders\[0\]\.name: a value of type object") as e:
        tessera.render(data.T, {"renders": [{"name": object()}]})
    assert e.value.key_path == "renders[0].name"
    with pytest.raises(TypeError, match="a YAML file name or a dict"):
        tessera.render(data.T, 42)


def test_bad_arrays_raise_clear_errors(scene):
    data, path, _ = scene
    with pytest.raises(TypeError, match=r"dtype int32 is not supported; allowed: uint8, int16, uint16, float32, float64"):
        tessera.render(data.T.astype(np.int32), path)
    with pytest.raises(TypeError, match=r"dtype >f4 is not supported \(non-native byte order"):
        tessera.render(data.T.astype(">f4"), path)
    with pytest.raises(ValueError, match="a 3D array is needed"):
        tessera.render(data[0], path)
    with pytest.raises(tessera.DataError, match="field"):  # a broadcast: every vertex shares bytes
        tessera.render(np.broadcast_to(np.float32(1), (4, 4, 4)), path)
    with pytest.raises(tessera.DataError, match="spacing"):
        tessera.render(data.T, path, spacing=(1, 0, 1))


def test_warnings_about_the_image(scene):
    data, path, _ = scene
    cfg = {"renders": [{"name": "a", "image": {"width": 8, "height": 8, "spp": 1}, "camera": {"position": [40, 30, 30]},
                        "transfer_function": {"range": [100, 200], "opacity": [[0, 0], [1, 1]]}}]}
    with pytest.warns(tessera.TesseraWarning, match="range"):
        tessera.render(data.T, cfg)


def test_render_errors_are_python_exceptions(scene):
    data, _, _ = scene
    cfg = {"tessera": {"memory_limit_mb": 1},
           "renders": [{"name": "a", "image": {"width": 4096, "height": 4096, "spp": 1}, "camera": {"position": [40, 30, 30]},
                        "transfer_function": {"opacity": [[0, 0], [1, 1]]}}]}
    with pytest.raises(tessera.RenderError, match="memory_limit_mb = 1 MiB"):
        tessera.render(data.T, cfg)


def test_the_gil_is_released_while_rendering(scene):
    """A Python thread keeps running while another thread renders."""
    data, path, _ = scene
    cfg = {"tessera": {"threads": 1},
           "renders": [{"name": "a", "image": {"width": 64, "height": 64, "spp": 64}, "camera": {"position": [40, 30, 30]},
                        "transfer_function": {"opacity": [[0, 0], [1, 1]]}}]}
    ticks, done = [0], threading.Event()

    def tick():
        while not done.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        start = time.perf_counter()
        tessera.render(data.T, cfg)
        elapsed = time.perf_counter() - start
        seen = ticks[0]
    finally:
        done.set()
        t.join()
    # With the GIL held the ticker would be frozen for the whole render
    assert elapsed < 0.05 or seen >= 5, f"{seen} ticks in {elapsed:.3f} s of rendering"
