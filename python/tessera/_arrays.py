"""From numpy arrays to the extension's field descriptors, without copying."""
import numpy as np

# Codes of tessera_dtype (tessera.h), in order; native byte order only
_DTYPES = {np.dtype(np.uint8): 0, np.dtype(np.int16): 1, np.dtype(np.uint16): 2,
           np.dtype(np.float32): 3, np.dtype(np.float64): 4}
ALLOWED = "uint8, int16, uint16, float32, float64"
# What the refused kinds of dtype are, by dtype.kind
_DTYPE_HINTS = {"b": " (booleans: use a.astype(np.uint8))", "c": " (complex: pass a.real, a.imag or abs(a))",
                "O": " (Python objects: build a numeric array)", "U": " (strings)", "S": " (bytes)",
                "V": " (a structured array: pass one field, a['name'])", "M": " (dates)", "m": " (time deltas)"}


def field_descriptor(array, what="volume"):
    """(array, data address, dtype code, dims, byte strides) of a 3D array, read in place.

    ``array`` is kept by the caller for as long as the address is used. Anything but a numpy
    array goes through np.asarray first (a list is copied; an ndarray never is). A masked
    array is refused: the values under its mask would be rendered.
    """
    if type(array) is np.ndarray:
        a = array  # the common case (a million domains' arrays): no conversion to try
    elif isinstance(array, np.ma.MaskedArray):
        raise TypeError(f"{what}: a numpy masked array is not accepted (the values under its mask "
                        f"would be rendered); pass a.filled(value), or a.data to render them all")
    else:
        try:
            a = np.asarray(array)
        except (TypeError, ValueError) as e:
            raise TypeError(f"{what}: a 3D array is needed, got {type(array).__name__}, which numpy "
                            f"cannot turn into one ({e})") from None
    if a.ndim != 3:
        raise ValueError(f"{what}: a 3D array is needed (volume[i, j, k] is vertex (i, j, k)), "
                         f"got {a.ndim} dimension(s) of shape {a.shape}")
    code = _DTYPES.get(a.dtype)
    if code is None:
        shown = a.dtype.name if a.dtype.isnative else a.dtype.str
        hint = _DTYPE_HINTS.get(a.dtype.kind, "")
        if not a.dtype.isnative:
            hint = " (non-native byte order: use a.astype(a.dtype.newbyteorder('=')))"
        raise TypeError(f"{what}: dtype {shown} is not supported{hint}; allowed: {ALLOWED}")
    if a.size == 0:
        raise ValueError(f"{what}: empty array of shape {a.shape}")
    address = a.__array_interface__["data"][0]
    return a, address, code, a.shape, a.strides  # tuples of Python ints



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
