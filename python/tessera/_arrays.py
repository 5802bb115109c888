"""From numpy arrays to the extension's field descriptors, without copying."""
import numpy as np

# Codes of tessera_dtype (tessera.h), in order; native byte order only
_DTYPES = {np.dtype(np.uint8): 0, np.dtype(np.int16): 1, np.dtype(np.uint16): 2,
           np.dtype(np.float32): 3, np.dtype(np.float64): 4}
ALLOWED = "uint8, int16, uint16, float32, float64"


def field_descriptor(array, what="volume"):
    """(array, data address, dtype code, dims, byte strides) of a 3D array, read in place.

    ``array`` is kept by the caller for as long as the address is used. Anything but a numpy
    array goes through np.asarray first (a list is copied; an ndarray never is).
    """
    a = np.asarray(array)
    if a.ndim != 3:
        raise ValueError(f"{what}: a 3D array is needed (volume[i, j, k] is vertex (i, j, k)), "
                         f"got {a.ndim} dimension(s) of shape {a.shape}")
    code = _DTYPES.get(a.dtype)
    if code is None:
        shown = a.dtype.name if a.dtype.isnative else a.dtype.str
        hint = "" if a.dtype.isnative else " (non-native byte order: use a.astype(a.dtype.newbyteorder('=')))"
        raise TypeError(f"{what}: dtype {shown} is not supported{hint}; allowed: {ALLOWED}")
    if a.size == 0:
        raise ValueError(f"{what}: empty array of shape {a.shape}")
    address = a.__array_interface__["data"][0]
    return a, address, code, tuple(int(n) for n in a.shape), tuple(int(s) for s in a.strides)


def triple(value, what, kind=float):
    """A number or three numbers as a tuple of three ``kind``."""
    if np.isscalar(value):
        return (kind(value),) * 3
    t = tuple(kind(v) for v in value)
    if len(t) != 3:
        raise ValueError(f"{what}: expected 3 values (x, y, z), got {len(t)}")
    return t

