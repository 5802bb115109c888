"""Device arrays from Python (docs/gpu_bindings.md): fields given by __cuda_array_interface__
(versions 2 and 3) or DLPack reach the adapter zero copy, with their byte strides, and
Adapter.set_cuda_stream takes the simulation's stream.

This machine has no GPU: the "device" arrays here describe a numpy array's host memory, so the
renderer reads host memory and the image must equal the numpy array's bit for bit. That tests
the plumbing (address, dtype, shape, strides, stream), never a GPU; the last test does, where
CuPy and a CUDA build of Tessera are present.
"""
import os
import sys

import numpy as np
import pytest

import tessera
import tessera._arrays as arrays
from conftest import field, same_bits

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mesh_example  # noqa: E402
from blueprint_meshes import uniform  # noqa: E402
from test_adapter import CONFIG, GRID  # noqa: E402


class FakeCudaArray:
    """__cuda_array_interface__ over a numpy array's host memory (the "device" pointer is a
    host address). ``changes`` replaces or (None) removes keys of the interface."""

    def __init__(self, a, version=3, stream=None, c_strides=False, **changes):
        self.base = a  # kept alive: the interface only points at it
        cai = {"shape": a.shape, "typestr": a.dtype.str, "data": (a.__array_interface__["data"][0], False),
               "version": version, "strides": None if c_strides else a.strides}
        if version is not None and version >= 3:
            cai["stream"] = stream
        for key, value in changes.items():
            if value is None:
                cai.pop(key, None)
            else:
                cai[key] = value
        self.__cuda_array_interface__ = cai


class FakeDLPackCuda:
    """A DLPack producer that says it lives on a CUDA device (its capsule is numpy's: host)."""

    def __init__(self, a):
        self.base = a

    def __dlpack__(self, **kw):
        return self.base.__dlpack__(**kw)

    def __dlpack_device__(self):
        return (2, 0)  # kDLCUDA, device 0


@pytest.fixture
def host_as_device(monkeypatch):
    """Lets the package take the fake device arrays in a build without CUDA (their memory is
    the host's; Tessera reads it as host memory)."""
    monkeypatch.setattr(arrays, "_cuda_built", lambda: True)


def adapter_image(tmp_path, fields, **kw):
    """(main image, result dict) of one execute at step 0 (CONFIG renders at every even step)."""
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        images = viz.execute(0, 0.0, fields, **GRID, **kw)
        assert viz.last_status == 0, viz.last_error
        return images["main"], viz.results[0]


# ---- The image: the same bits as the numpy array's ------------------------------------------

def test_cuda_array_interface_renders_as_numpy(tmp_path, host_as_device):
    data = field().T  # a transposed view: strides in bytes, not C order
    plain, result = adapter_image(tmp_path, {"temperature": data})
    assert plain[..., 3].max() > 0.1
    assert result["device"] == "cpu" and result["bytes_to_device"] == 0 and result["bytes_to_host"] == 0
    for version in (2, 3):
        got, result = adapter_image(tmp_path, {"temperature": FakeCudaArray(data, version=version)})
        assert same_bits(plain, got), version
        assert result["device"] == "cpu"


def test_strides_of_views_are_passed_in_bytes(tmp_path, host_as_device):
    big = np.ascontiguousarray(np.pad(field(dtype=np.float64), 2, constant_values=1e30).T)
    views = {"sliced": big[2:-2, 2:-2, 2:-2], "reversed": big[2:-2, 2:-2, 2:-2][::-1, :, ::-1],
             "fortran": np.asfortranarray(field(dtype=np.uint16).T)}
    for label, view in views.items():
        plain, _ = adapter_image(tmp_path, {"temperature": view})
        got, _ = adapter_image(tmp_path, {"temperature": FakeCudaArray(view)})
        assert same_bits(plain, got), label
    contiguous = np.ascontiguousarray(field().T)
    plain, _ = adapter_image(tmp_path, {"temperature": contiguous})
    got, _ = adapter_image(tmp_path, {"temperature": FakeCudaArray(contiguous, c_strides=True)})  # strides None
    assert same_bits(plain, got)


def test_render_and_every_execute_path_take_device_arrays(tmp_path, host_as_device):
    data = field().T
    assert same_bits(tessera.render(data, CONFIG, **GRID), tessera.render(FakeCudaArray(data), CONFIG, **GRID))
    plain, _ = adapter_image(tmp_path, {"temperature": data})
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        domains = viz.execute(0, 0.0, domains=[{"fields": {"temperature": FakeCudaArray(data)}}],
                              global_dims=data.shape, **GRID)["main"]
        flat = np.ascontiguousarray(data.T).ravel()  # Blueprint's order: i fastest
        blueprint = viz.execute_blueprint(0, 0.0, uniform(data, data.shape) | {
            "fields": {"temperature": {"association": "vertex", "topology": "topo",
                                       "values": FakeCudaArray(flat)}}})["main"]
    assert same_bits(plain, domains) and same_bits(plain, blueprint)


def test_blueprint_and_mesh_domain_fields_through_the_protocol(tmp_path, host_as_device):
    data = field().T
    plain, _ = adapter_image(tmp_path, {"temperature": data})
    dom = uniform(data, data.shape)
    dom["fields"]["temperature"]["values"] = FakeCudaArray(data.T)  # (nk, nj, ni): its .T is read
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        assert same_bits(plain, viz.execute_blueprint(0, 0.0, dom)["main"])
    xyz, f, hexes = mesh_example.shell()
    small = {"tessera": {"threads": 2, "on_error": "abort"},
             "renders": [{"field": "f", "image": {"width": 40, "height": 30, "spp": 4}}]}
    images = []
    for values in (f, FakeCudaArray(f), FakeCudaArray(f.reshape(mesh_example.NK, mesh_example.NJ, mesh_example.NI).T)):
        with tessera.Adapter(small, output_dir=str(tmp_path / "mesh"), quiet=True) as viz:
            images.append(viz.execute_mesh_domains(0, 0.0, [{"coords": xyz, "dims": (mesh_example.NI, mesh_example.NJ,
                                                                                     mesh_example.NK),
                                                             "fields": {"f": values}}])["f"])
    assert images[0][..., :3].std() > 0
    assert np.array_equal(images[0], images[1]) and np.array_equal(images[0], images[2])


def test_mesh_coordinates_and_connectivity_through_the_protocol(tmp_path, host_as_device):
    # A mesh's coordinates (an (n, 3) array or x, y, z) and connectivity may be device arrays
    # too: the adapter copies them to the host (here they are host memory already)
    xyz, f, hexes = mesh_example.shell()
    small = {"tessera": {"threads": 2, "on_error": "abort"},
             "renders": [{"field": "f", "image": {"width": 40, "height": 30, "spp": 4}}]}
    x, y, z = (np.ascontiguousarray(xyz[:, a]) for a in range(3))
    images = []
    for coords, conn in ((xyz, hexes), (FakeCudaArray(xyz), FakeCudaArray(hexes)),
                         ([FakeCudaArray(x), FakeCudaArray(y), FakeCudaArray(z)], hexes)):
        with tessera.Adapter(small, output_dir=str(tmp_path / "mesh"), quiet=True) as viz:
            images.append(viz.execute_mesh_domains(0, 0.0, [{"coords": coords, "shape": "hex",
                                                             "connectivity": conn, "fields": {"f": f}}])["f"])
    assert images[0][..., :3].std() > 0
    assert np.array_equal(images[0], images[1]) and np.array_equal(images[0], images[2])


def test_dlpack_capsules_and_cuda_producers(tmp_path, host_as_device):
    data = field(dtype=np.int16).T
    plain, _ = adapter_image(tmp_path, {"temperature": data})
    got, _ = adapter_image(tmp_path, {"temperature": FakeDLPackCuda(data)})
    assert same_bits(plain, got)
    got, _ = adapter_image(tmp_path, {"temperature": data.__dlpack__()})  # a bare capsule (host memory)
    assert same_bits(plain, got)


# ---- What is refused, and how --------------------------------------------------------------

@pytest.mark.parametrize("typestr, shown", [("<i4", "int32"), ("<c8", "complex64"), ("|b1", "bool"),
                                            ("<f2", "float16"), (">f4", ">f4"), ("<i8", "int64")])
def test_typestr_outside_the_five_dtypes_names_field_dtype_and_allowed(tmp_path, host_as_device, typestr, shown):
    fake = FakeCudaArray(field().T, typestr=typestr)
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        with pytest.raises(TypeError, match=rf"fields\['temperature'\]: dtype {shown} is not supported.*allowed: "
                                            rf"uint8, int16, uint16, float32, float64"):
            viz.execute(0, 0.0, {"temperature": fake}, **GRID)


def test_malformed_interfaces_are_refused(tmp_path, host_as_device):
    data = field().T
    cases = [
        (dict(version=1), TypeError, r"version 1 is not read \(versions 2 and 3 are\)"),
        (dict(version=4), TypeError, r"version 4 is not read"),
        (dict(version=None), TypeError, r"version None is not read"),
        (dict(data=None), TypeError, r"'data' must be a tuple \(pointer, read-only flag\), got None"),
        (dict(data=(0, False)), ValueError, r"a null data pointer for a non-empty array"),
        (dict(data=("0x10", False)), TypeError, r"'data' must be a tuple"),
        (dict(typestr="zz"), TypeError, r"dtype 'zz' is not supported \(not a typestr numpy knows\)"),
        (dict(shape=[20, 16, 12]), TypeError, r"'shape' must be a tuple"),
        (dict(strides=(4, 8)), TypeError, r"'strides' must be None or a tuple of 3 byte strides"),
        (dict(stream="default"), TypeError, r"'stream' must be None or a stream handle"),
        (dict(mask=(1, 2)), TypeError, r"a masked CUDA array is not accepted"),
        (dict(shape=(20, 16), strides=(4, 80)), ValueError, r"a 3D array is needed .* got 2 dimension\(s\)"),
    ]
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        for change, exception, message in cases:
            with pytest.raises(exception, match=message):
                viz.execute(0, 0.0, {"temperature": FakeCudaArray(data, **change)}, **GRID)
    with pytest.raises(TypeError, match=r"volume: dtype int32 is not supported"):
        tessera.render(FakeDLPackCuda(np.zeros((4, 4, 4), np.int32)), CONFIG)
    with pytest.raises(TypeError, match=r"volume: dtype bool is not supported"):
        tessera.render(np.zeros((4, 4, 4), np.bool_).__dlpack__(), CONFIG)


def test_without_cuda_device_arrays_are_refused_by_name():
    if tessera._tessera.cuda_built():
        pytest.skip("this Tessera is built with CUDA: device arrays are read")
    with pytest.raises(TypeError, match=r"volume: a CUDA device array \(__cuda_array_interface__\), but this "
                                        r"Tessera was built without CUDA"):
        tessera.render(FakeCudaArray(field().T), CONFIG)
    with pytest.raises(TypeError, match=r"DLPack, CUDA device 0.*built without CUDA"):
        tessera.render(FakeDLPackCuda(field().T), CONFIG)


def test_device_values_are_never_read_from_python(host_as_device):
    """The package reads only the description: a pointer nothing is behind is described, not
    dereferenced (the adapter is never called here)."""
    fake = FakeCudaArray(field().T, data=(0xDEAD0000, True))
    a, address, code, dims, strides = arrays.field_descriptor(fake, "f")
    assert address == 0xDEAD0000 and code == 3 and dims == (20, 16, 12) and strides == field().T.strides
    assert type(a) is arrays.DeviceArray and a.owner is fake and a.T.shape == (12, 16, 20)


# ---- Streams --------------------------------------------------------------------------------

class CupyLikeStream:
    ptr = 0x1  # cudaStreamLegacy: a valid handle wherever CUDA runs


class TorchLikeStream:
    cuda_stream = 0x2  # cudaStreamPerThread


def test_set_cuda_stream_takes_none_int_and_stream_objects(tmp_path):
    data = field().T
    plain, _ = adapter_image(tmp_path, {"temperature": data})
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        for stream in (None, 0, 1, np.uint64(2), CupyLikeStream(), TorchLikeStream(), None):
            viz.set_cuda_stream(stream)
            assert same_bits(plain, viz.execute(0, 0.0, {"temperature": data}, **GRID)["main"])
        for wrong, exception, message in [("1", TypeError, r"stream: None, an int .* got str"),
                                          (1.0, TypeError, r"got float"), (True, TypeError, r"got bool"),
                                          (-1, ValueError, r"-1 is not a cudaStream_t"),
                                          (2**64, ValueError, r"is not a cudaStream_t"),
                                          (type("S", (), {"ptr": "x"})(), TypeError,
                                           r"stream.ptr \(S\): an int \(the cudaStream_t\) is needed, got str")]:
            with pytest.raises(exception, match=message):
                viz.set_cuda_stream(wrong)
    with pytest.raises(tessera.TesseraError, match="set_cuda_stream: the adapter is closed"):
        viz.set_cuda_stream(None)


def test_the_producers_stream_is_used_for_the_call(tmp_path, host_as_device):
    data = field().T
    plain, _ = adapter_image(tmp_path, {"temperature": data})
    got, _ = adapter_image(tmp_path, {"temperature": FakeCudaArray(data, stream=1)})  # legacy default stream
    assert same_bits(plain, got)
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:  # a failure keeps its message
        with pytest.warns(tessera.TesseraWarning):
            viz.execute(0, 0.0, {"other": FakeCudaArray(data, stream=1)}, **GRID)
        assert viz.last_status == 2 and "temperature" in viz.last_error, viz.last_error
    held = [FakeCudaArray(data, stream=s) for s in (1, 1, None)]
    assert arrays.producer_stream([arrays.array_of(h, "f") for h in held]) == 1
    held.append(FakeCudaArray(data, stream=2))  # two streams: none chosen (the whole device is synchronised)
    assert arrays.producer_stream([arrays.array_of(h, "f") for h in held]) is None
    assert arrays.producer_stream([data]) is None
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        assert viz._call_stream([arrays.array_of(FakeCudaArray(data, stream=2), "f")]) == 2
        viz.set_cuda_stream(None)  # set: the adapter's own from now on
        assert viz._call_stream([arrays.array_of(FakeCudaArray(data, stream=2), "f")]) is None


# ---- On a GPU --------------------------------------------------------------------------------

def _cupy_device():
    try:
        import cupy
        return cupy if cupy.cuda.runtime.getDeviceCount() > 0 and tessera._tessera.cuda_built() else None
    except Exception:
        return None


@pytest.mark.skipif(_cupy_device() is None, reason="needs CuPy, a CUDA device and Tessera built with CUDA")
def test_cupy_array_rendered_in_place_on_the_gpu(tmp_path):
    cupy = _cupy_device()
    host = field().T
    data = cupy.asarray(np.ascontiguousarray(host))
    config = dict(CONFIG, tessera=dict(CONFIG["tessera"], device="cuda", on_error="abort"))
    stream = cupy.cuda.Stream(non_blocking=True)
    with stream:
        data = data * 1.0  # computed on the simulation's stream
    with tessera.Adapter(config, output_dir=tmp_path, quiet=True) as viz:
        viz.set_cuda_stream(stream)
        image = viz.execute(0, 0.0, {"temperature": data}, **GRID)["main"]
        result = viz.results[0]
    assert result["device"].startswith("cuda"), result["device"]
    assert result["bytes_to_device"] < data.nbytes  # no field bytes: read in place
    assert image.shape == (24, 32, 4) and np.all(np.isfinite(image)) and image[..., 3].max() > 0.1
