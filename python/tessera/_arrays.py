"""From arrays to the extension's field descriptors, without copying: the package's one reader
of the array protocols (numpy's ``__array_interface__``, ``__cuda_array_interface__`` versions 2
and 3, DLPack). A device array's values are never touched here: only its description."""
import numbers

import numpy as np

from . import _tessera

# Codes of tessera_dtype (tessera.h), in order; native byte order only
_DTYPES = {np.dtype(np.uint8): 0, np.dtype(np.int16): 1, np.dtype(np.uint16): 2,
           np.dtype(np.float32): 3, np.dtype(np.float64): 4}
ALLOWED = "uint8, int16, uint16, float32, float64"
# What the refused kinds of dtype are, by dtype.kind
_DTYPE_HINTS = {"b": " (booleans: use a.astype(np.uint8))", "c": " (complex: pass a.real, a.imag or abs(a))",
                "O": " (Python objects: build a numeric array)", "U": " (strings)", "S": " (bytes)",
                "V": " (a structured array: pass one field, a['name'])", "M": " (dates)", "m": " (time deltas)"}


_CAI_VERSIONS = (2, 3)  # __cuda_array_interface__ versions read (CuPy, Numba: 3; PyTorch: 2)
_DL_CPU, _DL_CUDA, _DL_CUDA_HOST, _DL_CUDA_MANAGED = 1, 2, 3, 13  # DLDeviceType
_DL_DEVICES = {_DL_CPU: "CPU", _DL_CUDA: "CUDA", _DL_CUDA_HOST: "CUDA host (pinned)", _DL_CUDA_MANAGED: "CUDA managed"}
_DL_KINDS = {0: "int", 1: "uint", 2: "float", 4: "bfloat", 5: "complex", 6: "bool"}  # DLDataTypeCode
_DL_NUMPY = {0: "i", 1: "u", 2: "f", 5: "c"}  # the DLDataTypeCodes numpy has, as typestr kinds
_cuda = []  # whether this build holds the CUDA backend, asked once


def _cuda_built():
    """True when Tessera was built with CUDA (it can then read device memory). The tests of the
    protocols replace it: their "device" arrays point at host memory."""
    if not _cuda:
        _cuda.append(bool(_tessera.cuda_built()))
    return _cuda[0]


class DeviceArray:
    """A CUDA array as its protocol describes it (``__cuda_array_interface__`` or DLPack): what
    numpy tells of a host array (shape, strides in bytes, dtype, ndim, size, flags), its first
    element's ``address`` and the producer's ``stream`` (an int, or None); never its values.
    ``owner`` (the array, and the DLPack tensor) is held with it for as long as the address is
    used. ``on_device``: device or managed memory (False for a DLPack tensor on the CPU)."""
    __slots__ = ("owner", "address", "dtype", "shape", "strides", "stream", "on_device")

    def __init__(self, owner, address, dtype, shape, strides, stream=None, on_device=True):
        self.owner, self.address, self.dtype = owner, address, dtype
        self.shape, self.strides, self.stream, self.on_device = tuple(shape), tuple(strides), stream, on_device

    @property
    def ndim(self):
        return len(self.shape)

    @property
    def size(self):
        n = 1
        for s in self.shape:
            n *= s
        return n

    @property
    def flags(self):
        """numpy's ALIGNED and C_CONTIGUOUS, from the description."""
        item = self.dtype.itemsize
        contiguous, expect = True, item
        for n, s in zip(reversed(self.shape), reversed(self.strides)):
            contiguous &= n == 1 or s == expect
            expect *= n
        aligned = self.address % item == 0 and all(s % item == 0 for s in self.strides)
        return {"ALIGNED": aligned, "C_CONTIGUOUS": contiguous}

    @property
    def T(self):
        return self.strided(tuple(reversed(self.shape)), tuple(reversed(self.strides)))

    def strided(self, shape, strides):
        """Another view of the same memory (numpy's as_strided, without numpy)."""
        return DeviceArray(self.owner, self.address, self.dtype, shape, strides, self.stream, self.on_device)

    def __repr__(self):
        return f"DeviceArray(shape={self.shape}, dtype={self.dtype.name}, strides={self.strides})"


def _refuse_dtype(what, shown, hint=""):
    raise TypeError(f"{what}: dtype {shown} is not supported{hint}; allowed: {ALLOWED}")


def _int(value):
    return type(value) is int or (isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_)))


def _need_cuda(what, protocol):
    if not _cuda_built():
        raise TypeError(f"{what}: a CUDA device array ({protocol}), but this Tessera was built without CUDA "
                        f"(TESSERA_CUDA=OFF, or no CUDA compiler found) and cannot read device memory; pass a "
                        f"host copy (cupy.asnumpy(a), t.cpu().numpy()) or build Tessera with CUDA")


def _from_cuda_array_interface(value, cai, what):
    """The DeviceArray of an object's ``__cuda_array_interface__`` (versions 2 and 3)."""
    bad = f"{what}: {type(value).__name__}.__cuda_array_interface__"
    if not isinstance(cai, dict):
        raise TypeError(f"{bad}: a dict is needed, got {type(cai).__name__}")
    version = cai.get("version")
    if not _int(version) or version not in _CAI_VERSIONS:
        raise TypeError(f"{bad}: version {version!r} is not read (versions 2 and 3 are)")
    shape, typestr, data = cai.get("shape"), cai.get("typestr"), cai.get("data")
    if not isinstance(shape, tuple) or not all(_int(n) and n >= 0 for n in shape):
        raise TypeError(f"{bad}: 'shape' must be a tuple of sizes, got {shape!r}")
    if not isinstance(typestr, str):
        raise TypeError(f"{bad}: 'typestr' must be a str (e.g. '<f4'), got {typestr!r}")
    try:
        dtype = np.dtype(typestr)
    except TypeError:
        _refuse_dtype(what, repr(typestr), " (not a typestr numpy knows)")
    if not isinstance(data, tuple) or len(data) != 2 or not _int(data[0]):
        raise TypeError(f"{bad}: 'data' must be a tuple (pointer, read-only flag), got {data!r}")
    if cai.get("mask") is not None:
        raise TypeError(f"{what}: a masked CUDA array is not accepted (the values under its mask would be "
                        f"rendered); pass one without a mask")
    strides = cai.get("strides")
    if strides is None:  # C-contiguous
        strides, step = [], dtype.itemsize
        for n in reversed(shape):
            strides.insert(0, step)
            step *= n
    elif not isinstance(strides, tuple) or len(strides) != len(shape) or not all(_int(s) for s in strides):
        raise TypeError(f"{bad}: 'strides' must be None or a tuple of {len(shape)} byte strides, got {strides!r}")
    stream = cai.get("stream") if version >= 3 else None
    if stream is not None and (not _int(stream) or stream < 0):
        raise TypeError(f"{bad}: 'stream' must be None or a stream handle (an int), got {stream!r}")
    if data[0] == 0 and all(shape):
        raise ValueError(f"{bad}: a null data pointer for a non-empty array of shape {shape}")
    _need_cuda(what, "__cuda_array_interface__")
    stream = int(stream) if stream else None  # 0 (disallowed by version 3): as None, the whole device
    return DeviceArray(value, int(data[0]), dtype, tuple(int(n) for n in shape), tuple(int(s) for s in strides),
                       stream)


def _from_dlpack(value, what):
    """The DeviceArray of a DLPack tensor (a capsule, or an object with ``__dlpack__``) on a CUDA
    device (or the CPU: host memory, as a capsule may be)."""
    try:
        tensor = _tessera._dlpack_tensor(value)
    except TypeError as e:
        raise TypeError(f"{what}: {type(value).__name__} could not be read through DLPack ({e})") from None
    device = tensor.device_type
    if device not in _DL_DEVICES:
        raise TypeError(f"{what}: a DLPack tensor on device type {device} is not accepted (the CPU, CUDA and CUDA "
                        f"managed memory are)")
    code, bits, lanes = tensor.dtype_code, tensor.bits, tensor.lanes
    shown = f"{_DL_KINDS.get(code, f'code {code} ')}{bits}" + (f"x{lanes}" if lanes != 1 else "")
    dtype = None
    if lanes == 1 and code == 6 and bits == 8:
        dtype = np.dtype(np.bool_)
    elif lanes == 1 and code in _DL_NUMPY and bits in (8, 16, 32, 64, 128):
        try:
            dtype = np.dtype(f"{_DL_NUMPY[code]}{bits // 8}")
        except TypeError:
            pass
    if dtype is None:  # no numpy dtype (bfloat16, vectors): the callers' check could not name it
        _refuse_dtype(what, shown)
    on_device = device in (_DL_CUDA, _DL_CUDA_MANAGED)
    if on_device:
        _need_cuda(what, f"DLPack, {_DL_DEVICES[device]} device {tensor.device_id}")
    return DeviceArray((value, tensor), tensor.address, dtype, tensor.shape, tensor.byte_strides, None, on_device)


def array_of(value, what):
    """``value`` as Tessera reads it in place: a numpy array (itself; or np.asarray of something
    numpy reads, a list being copied) or a DeviceArray (``__cuda_array_interface__``, or DLPack
    on a CUDA device, or a DLPack capsule). A masked array is refused: the values under its
    mask would be rendered."""
    if type(value) is np.ndarray or type(value) is DeviceArray:
        return value
    if isinstance(value, np.ma.MaskedArray):
        raise TypeError(f"{what}: a numpy masked array is not accepted (the values under its mask "
                        f"would be rendered); pass a.filled(value), or a.data to render them all")
    try:
        cai = value.__cuda_array_interface__  # a CPU tensor of PyTorch raises AttributeError
    except AttributeError:
        cai = None
    if cai is not None:
        return _from_cuda_array_interface(value, cai, what)
    if type(value).__name__ == "PyCapsule":
        return _from_dlpack(value, what)
    if hasattr(value, "__dlpack__") and hasattr(value, "__dlpack_device__") and not isinstance(value, np.ndarray):
        device = value.__dlpack_device__()
        if isinstance(device, tuple) and device and device[0] in (_DL_CUDA, _DL_CUDA_MANAGED):
            _need_cuda(what, f"DLPack, {_DL_DEVICES[device[0]]} device {device[1] if len(device) > 1 else 0}")
            return _from_dlpack(value, what)
    if isinstance(value, np.ndarray):
        return value
    try:
        return np.asarray(value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{what}: a 3D array is needed, got {type(value).__name__}, which numpy cannot turn into "
                        f"one ({e})") from None


def address_of(a):
    """The first element's address of what array_of gave."""
    return a.__array_interface__["data"][0] if type(a) is not DeviceArray else a.address


def is_array(value):
    """Whether ``value`` is an array read in place: a numpy array or a CUDA one (by its protocol),
    checked without reading it."""
    if isinstance(value, (np.ndarray, DeviceArray)) or type(value).__name__ == "PyCapsule":
        return True
    try:
        if value.__cuda_array_interface__ is not None:
            return True
    except AttributeError:
        pass
    return hasattr(value, "__dlpack__") and hasattr(value, "__dlpack_device__")


def producer_stream(held):
    """The one CUDA stream the device arrays among ``held`` name (``__cuda_array_interface__``
    version 3), or None: none named, or several (the whole device is then synchronised)."""
    streams = {a.stream for a in held if type(a) is DeviceArray and a.stream is not None}
    return streams.pop() if len(streams) == 1 else None


def uses_device_protocol(held):
    """Whether any of ``held`` came through a CUDA protocol (its memory may be a device's)."""
    return any(type(a) is DeviceArray and a.on_device for a in held)


def cuda_stream_address(stream):
    """The cudaStream_t of ``stream`` as an int: None (0: none), an int (the raw handle), or an
    object with ``.ptr`` (CuPy's Stream) or ``.cuda_stream`` (PyTorch's torch.cuda.Stream)."""
    if stream is None:
        return 0
    handle, source = stream, "stream"
    if not _int(stream):
        for attribute in ("ptr", "cuda_stream"):
            if hasattr(stream, attribute):
                handle, source = getattr(stream, attribute), f"stream.{attribute} ({type(stream).__name__})"
                break
        else:
            raise TypeError(f"stream: None, an int (the cudaStream_t) or a stream object with .ptr (CuPy) or "
                            f".cuda_stream (PyTorch) is needed, got {type(stream).__name__}")
    if not _int(handle):
        raise TypeError(f"{source}: an int (the cudaStream_t) is needed, got {type(handle).__name__}")
    if not 0 <= int(handle) < 2**64:
        raise ValueError(f"{source}: {int(handle)} is not a cudaStream_t (an address: 0 .. 2**64 - 1)")
    return int(handle)


def field_descriptor(array, what="volume"):
    """(array held, data address, dtype code, dims, byte strides) of a 3D array, read in place.

    ``array`` is kept by the caller for as long as the address is used: a numpy array or a
    DeviceArray (array_of: anything else goes through np.asarray, a list being copied; an
    ndarray never is). A masked array is refused: the values under its mask would be rendered.
    """
    a = array if type(array) is np.ndarray else array_of(array, what)
    if a.ndim != 3:
        raise ValueError(f"{what}: a 3D array is needed (volume[i, j, k] is vertex (i, j, k)), "
                         f"got {a.ndim} dimension(s) of shape {a.shape}")
    code = _DTYPES.get(a.dtype)
    if code is None:
        shown = a.dtype.name if a.dtype.isnative else a.dtype.str
        hint = _DTYPE_HINTS.get(a.dtype.kind, "")
        if not a.dtype.isnative:
            hint = " (non-native byte order: use a.astype(a.dtype.newbyteorder('=')))"
        _refuse_dtype(what, shown, hint)
    if a.size == 0:
        raise ValueError(f"{what}: empty array of shape {a.shape}")
    return a, address_of(a), code, a.shape, a.strides  # tuples of Python ints


def coordinate_array(value, what, n, why):
    """A rectilinear axis' coordinates, read in place: a 1-D, C-contiguous, aligned float64
    numpy array (native byte order) of exactly ``n`` values; ``why`` says where ``n`` comes
    from. Anything else is refused with what it is (never copied or converted: a masked array
    would hand over the values under its mask)."""
    if isinstance(value, np.ma.MaskedArray):
        raise TypeError(f"{what}: a numpy masked array is not accepted (the coordinates under its mask "
                        f"would be used); pass c.filled(value), or c.data to use them all")
    if not isinstance(value, np.ndarray):
        raise TypeError(f"{what}: a 1-D float64 numpy array of {n} values is needed ({why}), got "
                        f"{type(value).__name__} (np.asarray(c, dtype=np.float64) makes one)")
    problems = []
    if value.dtype != np.dtype(np.float64):
        problems.append(f"dtype {value.dtype.name if value.dtype.isnative else value.dtype.str}")
    if value.ndim != 1:
        problems.append(f"{value.ndim} dimension(s) of shape {value.shape}")
    elif value.shape[0] != n:
        problems.append(f"{value.shape[0]} values")
    if not value.flags["C_CONTIGUOUS"]:
        problems.append("a strided view (np.ascontiguousarray(c) copies it)")
    elif not value.flags["ALIGNED"]:
        problems.append("unaligned memory")
    if problems:
        raise ValueError(f"{what}: a 1-D contiguous float64 array of {n} values is needed ({why}), got "
                         f"{', '.join(problems)}")
    return value
