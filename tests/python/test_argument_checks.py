"""Arguments of tessera.render and tessera.Adapter are checked, never converted: a float or str
step, float ghosts or dims, a str spacing, a NUL inside a name or path, a masked array are
refused with a message naming the argument (docs/python.md, "Arguments")."""
import pathlib
import re

import numpy as np
import pytest

import tessera
from conftest import field, same_bits, write_scene
from test_adapter import CONFIG, GRID

NUL_CUT = "contains a NUL character at position"


@pytest.fixture
def data():
    return field().T  # (20, 16, 12) float32


@pytest.fixture
def viz(tmp_path):
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as v:
        yield v


# ---- tessera.render ------------------------------------------------------------------------

@pytest.mark.parametrize("spacing", ["1.5", (1, "1.5", 2), (1.0, 1.0, 1j), b"abc", {"x": 1}])
def test_render_refuses_a_spacing_that_is_not_numbers(data, spacing):
    with pytest.raises(TypeError, match=r"^spacing(\[\d\])?: a (real number|number or 3 numbers)"):
        tessera.render(data, CONFIG, spacing=spacing)


def test_render_names_the_axis_of_a_non_finite_origin(data):
    with pytest.raises(tessera.DataError, match=r"origin\[1\] \(y\) = nan: must be finite"):
        tessera.render(data, CONFIG, origin=(0.0, np.nan, 0.0))


def test_render_refuses_a_nul_in_the_config_path_and_the_render_name(data, tmp_path):
    path = write_scene(str(tmp_path), data.T)
    tessera.render(data, path)  # the path itself is fine
    with pytest.raises(ValueError, match=f"config: .*{NUL_CUT} {len(path)}"):
        tessera.render(data, path + "\0.bak")
    with pytest.raises(ValueError, match=f"render: 'main\\\\x00x' {NUL_CUT} 4"):
        tessera.render(data, path, render="main\0x")


def test_render_takes_a_numpy_integer_step_and_index_as_ints(data, tmp_path):
    path = write_scene(str(tmp_path), data.T)
    ref = tessera.render(data, path, render=1, step=3)
    assert same_bits(tessera.render(data, pathlib.Path(path), render=np.int64(1), step=np.int32(3)), ref)
    with pytest.raises(TypeError, match=r"render: a render name or an index >= 0 is needed, got float 1.0"):
        tessera.render(data, path, render=1.0)


def test_render_refuses_a_masked_array(data):
    masked = np.ma.masked_array(data, mask=data > 0.5)
    with pytest.raises(TypeError, match="volume: a numpy masked array is not accepted"):
        tessera.render(masked, CONFIG)


@pytest.mark.parametrize("dtype, words", [(bool, r"dtype bool is not supported \(booleans"),
                                          (np.complex64, r"dtype complex64 is not supported \(complex"),
                                          (object, r"dtype object is not supported \(Python objects")])
def test_render_names_an_unsupported_dtype_and_what_to_do(dtype, words):
    with pytest.raises(TypeError, match="volume: " + words):
        tessera.render(np.zeros((4, 4, 4), dtype=dtype), CONFIG)


def test_render_names_the_volume_numpy_cannot_read():
    with pytest.raises(TypeError, match="volume: a 3D array is needed, got list"):
        tessera.render([[[0.0, 1.0]], [[0.0]]], CONFIG)  # ragged


# ---- tessera.Adapter -----------------------------------------------------------------------

@pytest.mark.parametrize("kw, message", [
    ({"output_dir": 5}, r"output_dir: a path \(str or os.PathLike\) is needed, got int 5"),
    ({"output_dir": "out\0put"}, f"output_dir: 'out\\\\x00put' {NUL_CUT} 3"),
    ({"quiet": "no"}, r"quiet: True or False is needed, got str 'no'"),
    ({"comm": object()}, r"comm: an mpi4py communicator or None is needed, got object"),
])
def test_adapter_refuses_bad_construction_arguments(kw, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # where an unchecked output_dir would be made
    kw.setdefault("output_dir", tmp_path)
    with pytest.raises((TypeError, ValueError), match=message):
        tessera.Adapter(CONFIG, **kw)


@pytest.mark.parametrize("step, shown", [(2.0, "float 2.0"), (2.5, "float 2.5"), ("2", "str '2'"),
                                         (True, "bool True"), (np.float64(2), "float64 2.0")])
def test_execute_refuses_a_step_that_is_not_an_integer(viz, data, step, shown):
    with pytest.raises(TypeError, match=f"^step: an integer is needed, got {shown}$"):
        viz.execute(step, 0.0, {"temperature": data}, **GRID)
    assert viz.results == []  # nothing was rendered


@pytest.mark.parametrize("time, shown", [("0.5", "str '0.5'"), (1j, "complex 1j"), (False, "bool False")])
def test_execute_refuses_a_time_that_is_not_a_real_number(viz, data, time, shown):
    with pytest.raises(TypeError, match=f"^time: a real number is needed, got {shown}$"):
        viz.execute(2, time, {"temperature": data}, **GRID)


@pytest.mark.parametrize("kw, name", [({"ghosts": 1.0}, "ghosts"), ({"ghosts": (0, 0, 1.5)}, r"ghosts\[2\]"),
                                      ({"ghosts_hi": np.array([0.0, 0.0, 0.0])}, r"ghosts_hi\[0\]"),
                                      ({"global_dims": (20.0, 16, 12)}, r"global_dims\[0\]"),
                                      ({"offset": "0"}, "offset")])
def test_execute_refuses_float_ghosts_dims_and_offsets(viz, data, kw, name):
    with pytest.raises(TypeError, match=f"^{name}: an integer is needed|^{name}: a number or 3"):
        viz.execute(2, 1.0, {"temperature": data}, **GRID, **kw)
    assert viz.results == []


def test_execute_refuses_a_spacing_string_and_a_flag_that_is_not_a_bool(viz, data):
    with pytest.raises(TypeError, match=r"^spacing: a number or 3 numbers \(x, y, z\) are needed, got str"):
        viz.execute(2, 1.0, {"temperature": data}, spacing="1.0")
    with pytest.raises(TypeError, match=r"^final: True or False is needed, got str 'yes'"):
        viz.execute(2, 1.0, {"temperature": data}, **GRID, final="yes")


def test_execute_refuses_field_names_that_are_not_plain_str(viz, data):
    with pytest.raises(ValueError, match=f"fields key: 'temperature\\\\x00old' {NUL_CUT} 11"):
        viz.execute(2, 1.0, {"temperature\0old": data}, **GRID)
    with pytest.raises(TypeError, match="fields key: a str is needed, got int 7"):
        viz.execute(2, 1.0, {7: data}, **GRID)
    assert viz.results == []


def test_execute_refuses_a_masked_field(viz, data):
    masked = np.ma.masked_invalid(data)
    with pytest.raises(TypeError, match=r"fields\['temperature'\]: a numpy masked array is not accepted"):
        viz.execute(2, 1.0, {"temperature": masked}, **GRID)


def test_execute_takes_numpy_scalars_and_arrays_of_the_right_kind(tmp_path, data):
    """numpy integers and reals are what simulations hold: taken as the Python numbers."""
    with tessera.Adapter(CONFIG, output_dir=tmp_path / "a", quiet=np.True_) as viz:
        ref = viz.execute(2, 1.0, {"temperature": data}, spacing=(1.0, 1.5, 2.0), origin=(-3, 0, 1),
                          global_dims=(20, 16, 12), offset=0, ghosts=0, final=False)["main"]
    with tessera.Adapter(CONFIG, output_dir=tmp_path / "b", quiet=True) as viz:
        img = viz.execute(np.int64(2), np.float32(1.0), {"temperature": data}, spacing=np.array([1.0, 1.5, 2.0]),
                          origin=np.array([-3, 0, 1]), global_dims=np.array([20, 16, 12]), offset=np.int32(0),
                          ghosts=np.zeros(3, dtype=np.int16), final=np.False_)["main"]
    assert same_bits(img, ref)


# ---- messages that name the argument, the item and the fault (issue 40, item 8) ------------

NOT_UTF8 = "is not valid UTF-8 text: '\\\\udcff' at position"


def test_names_and_paths_that_are_not_utf8_name_the_argument_and_position(viz, data, tmp_path):
    """A lone surrogate (Python's stand-in for a byte of a file name that is not UTF-8) has
    no UTF-8 form: refused naming the argument and the position, not nanobind's
    "incompatible function arguments"."""
    bad = "temp\udcff"
    with pytest.raises(ValueError, match=f"^fields key: 'temp\\\\udcff' {NOT_UTF8} 4"):
        viz.execute(2, 1.0, {bad: data}, **GRID)
    with pytest.raises(ValueError, match=rf"^domains\[0\]\['fields'\] key: .*{NOT_UTF8} 4"):
        viz.execute(2, 1.0, domains=[{"fields": {bad: data}}], global_dims=data.shape, **GRID)
    with pytest.raises(ValueError, match=f"^output_dir: .*{NOT_UTF8} 3"):
        tessera.Adapter(CONFIG, output_dir="out\udcff")
    with pytest.raises(ValueError, match=f"^config: .*{NOT_UTF8} 1"):
        tessera.Adapter(pathlib.Path("v\udcff.yaml"))
    with pytest.raises(ValueError, match=f"^render: .*{NOT_UTF8} 4"):
        tessera.render(data, CONFIG, render="main\udcff")
    with pytest.raises(tessera.ConfigError, match=rf"^config dict: renders\[0\]\.name: .*{NOT_UTF8} 1") as e:
        tessera.render(data, {"renders": [dict(CONFIG["renders"][0], name="m\udcff")]})
    assert e.value.key_path == "renders[0].name"


def test_integers_beyond_float_range_name_the_argument(viz, data):
    huge = 10 ** 400  # an int without a float value
    with pytest.raises(ValueError, match=r"^time: int \(an integer of about 401 digits\) is beyond the range of a float"):
        viz.execute(2, huge, {"temperature": data}, **GRID)
    with pytest.raises(ValueError, match=r"^spacing\[1\]: int .* is beyond the range of a float"):
        viz.execute(2, 1.0, {"temperature": data}, spacing=(1, huge, 1))
    with pytest.raises(ValueError, match=r"^origin: int .* is beyond the range of a float"):
        tessera.render(data, CONFIG, origin=-huge)
    with pytest.raises(ValueError, match=r"^step: -\(an integer of about 5001 digits\) is outside the 64-bit range"):
        viz.execute(-10 ** 5000, 1.0, {"temperature": data}, **GRID)  # too long for str(): still named
    with pytest.raises(tessera.ConfigError, match=r"^config dict: renders\[0\]\.image\.width: int .* beyond the range"):
        tessera.render(data, {"renders": [dict(CONFIG["renders"][0], image={"width": huge})]})
    assert viz.results == []


def test_an_empty_field_or_render_name_is_refused(viz, data):
    """"" would publish a field no render can name (the render then blamed a missing field),
    or select the first render silently."""
    with pytest.raises(ValueError, match="^fields key: an empty name is not allowed"):
        viz.execute(2, 1.0, {"": data}, **GRID)
    with pytest.raises(ValueError, match=r"^domains\[0\]\['fields'\] key: an empty name is not allowed"):
        viz.execute(2, 1.0, domains=[{"fields": {"": data}}], global_dims=data.shape, **GRID)
    with pytest.raises(ValueError, match="^render: an empty name is not allowed"):
        tessera.render(data, CONFIG, render="")
    assert viz.results == []


def endless(limit=1000):
    """An iterator of ones that fails the test when read past ``limit`` items (an endless one
    would take memory until it runs out)."""
    for _ in range(limit):
        yield 1
    raise AssertionError(f"read more than {limit} items where 3 numbers are expected")


@pytest.mark.parametrize("kw", ["spacing", "origin", "ghosts", "ghosts_hi", "global_dims", "offset"])
def test_an_endless_iterator_for_three_numbers_is_refused_after_four(viz, data, kw):
    with pytest.raises(ValueError, match=f"^{kw}: expected 3 values \\(x, y, z\\), got more than 3$"):
        viz.execute(2, 1.0, {"temperature": data}, **{kw: endless()})
    with pytest.raises(ValueError, match="^global_dims: expected 3 values"):
        viz.execute(2, 1.0, domains=[], global_dims=endless())
    with pytest.raises(ValueError, match="^spacing: expected 3 values"):
        tessera.render(data, CONFIG, spacing=endless())


def test_a_masked_coordinate_array_is_refused(viz, data):
    """Its masked values would be used as coordinates (the mask is not seen through the array's memory)."""
    y = np.ma.masked_array(np.linspace(0.0, 24.0, data.shape[1]), mask=np.arange(data.shape[1]) == 3)
    with pytest.raises(TypeError, match=r"^coords\[1\]: a numpy masked array is not accepted"):
        viz.execute(2, 1.0, domains=[{"fields": {"temperature": data}}], global_dims=data.shape,
                    coords=(None, y, None), **GRID)
    assert viz.results == []


@pytest.mark.parametrize("axis, words", [
    ([0.0, 1.0], r"got list \(np\.asarray\(c, dtype=np\.float64\) makes one\)"),
    (np.arange(16, dtype=np.float32), "got dtype float32$"),
    (np.arange(32.0)[::2], r"got a strided view \(np\.ascontiguousarray\(c\) copies it\)$"),
    (np.zeros((4, 4)), r"got 2 dimension\(s\) of shape \(4, 4\)$"),
    (np.arange(17.0), "got 17 values$"),
])
def test_a_refused_coordinate_array_says_what_was_given(viz, data, axis, words):
    with pytest.raises((TypeError, ValueError),
                       match=rf"^coords\[1\]: a 1-D (contiguous )?float64 (numpy )?array of 16 values is needed "
                             rf"\(global_dims\[1\] = 16, vertex data\), {words}"):
        viz.execute(2, 1.0, domains=[], global_dims=data.shape, coords=(None, axis, None), **GRID)
    with pytest.raises(TypeError, match=r"^coords: None or a list of three entries .*, got 2 entries$"):
        viz.execute(2, 1.0, domains=[], global_dims=data.shape, coords=(None, None), **GRID)


def test_the_binding_checks_coordinate_lengths_itself(viz, data):
    """Under the package's check, the extension never hands C an axis shorter than the mesh
    claims (issue 40 item 1: nothing C could read past)."""
    with pytest.raises(ValueError, match=r"coords\[1\]: 3 values for global_dims\[1\] = 16"):
        viz._impl.execute_domains(2, 1.0, 0, (0.0,) * 3, (1.0,) * 3, [None, np.zeros(3), None], data.shape, 1, [],
                                  [], False)
    with pytest.raises(ValueError, match="refinement: nlevels - 1 ratios are needed"):
        viz._impl.execute_domains(2, 1.0, 0, (0.0,) * 3, (1.0,) * 3, [None] * 3, data.shape, 3, [2], [], False)


@pytest.mark.parametrize("value, where, words", [
    (float("nan"), "renders[0].image.width", "nan is not allowed"),
    (object(), "renders[0].image.width", "a value of type object is not allowed"),
    ({(1, 2): 3}, "renders[0].image.width", r"key tuple \(1, 2\) is not a str"),
    ({1: 3}, "renders[0].image.width", "key int 1 is not a str"),
    ({"a\0b": 1}, "renders[0].image.width", "key: 'a\\\\x00b' contains a NUL character at position 1"),
    (iter([1, 2]), "renders[0].image.width", "a value of type list_iterator is not allowed"),
])
def test_dict_config_errors_name_the_key_path(data, value, where, words):
    cfg = {"renders": [dict(CONFIG["renders"][0], image={"width": value})]}
    with pytest.raises(tessera.ConfigError, match=rf"^config dict: {re.escape(where)}:? .*{words}") as e:
        tessera.render(data, cfg)
    assert e.value.key_path == where and e.value.file == "config dict"


def test_dict_config_that_contains_itself_or_nests_too_deep_is_refused(data):
    loop = {"width": 8}
    loop["again"] = loop
    with pytest.raises(tessera.ConfigError, match=r"^config dict: renders\[0\]\.image\.again: contains itself"):
        tessera.render(data, {"renders": [dict(CONFIG["renders"][0], image=loop)]})
    deep = []
    for _ in range(10000):
        deep = [deep]
    with pytest.raises(tessera.ConfigError, match=r"^config dict: renders(\[0\])+: nested more than 64 levels deep"):
        tessera.render(data, {"renders": deep})
