"""Checks of the public functions' arguments: a value of the wrong kind is refused with a
message naming the argument and what was given, never converted (no ``int(1.5)``, no
``float("2")``, no name cut at a NUL, no text that is not UTF-8)."""
import itertools
import math
import numbers
import os

import numpy as np

from ._errors import DataError


def _int_text(value):
    """An int as digits, or as its size when it is too long to print (Python refuses to
    print ints of more than 4300 digits)."""
    if abs(value).bit_length() <= 200:
        return str(value)
    digits = int(abs(value).bit_length() * math.log10(2)) + 1
    return f"{'-' if value < 0 else ''}(an integer of about {digits} digits)"


def _shown(value):
    """``float 1.5``, ``str '3'``: the type and a short repr of what was given."""
    if isinstance(value, int) and not isinstance(value, bool):
        text = _int_text(value)
    elif isinstance(value, np.ndarray):
        return f"ndarray of shape {value.shape} and dtype {value.dtype}"
    else:
        text = str(value) if isinstance(value, np.generic) else repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    return f"{type(value).__name__} {text}"


def _is_bool(value):
    return isinstance(value, (bool, np.bool_))


def integer(value, what, bits=64):
    """``value`` as an int: a Python or numpy integer (not a bool) within the signed ``bits``
    range. TypeError for anything else (a float, even 2.0; a str), ValueError out of range."""
    if type(value) is not int and (_is_bool(value) or not isinstance(value, numbers.Integral)):
        raise TypeError(f"{what}: an integer is needed, got {_shown(value)}")
    v = int(value)
    if not -2**(bits - 1) <= v < 2**(bits - 1):
        raise ValueError(f"{what}: {_int_text(v)} is outside the {bits}-bit range")
    return v


def real(value, what):
    """``value`` as a float: a Python or numpy real number (an int is one; a bool, str or
    complex is not: TypeError). ValueError for one beyond the range of a float (an int of
    10**400: it has no float value)."""
    if _is_bool(value) or not isinstance(value, numbers.Real):
        raise TypeError(f"{what}: a real number is needed, got {_shown(value)}")
    try:
        return float(value)
    except OverflowError:
        raise ValueError(f"{what}: {_shown(value)} is beyond the range of a float "
                         f"(about +-1.8e308)") from None


def flag(value, what):
    """``value`` as a bool: True or False (a numpy bool too); TypeError for anything else."""
    if not _is_bool(value):
        raise TypeError(f"{what}: True or False is needed, got {_shown(value)}")
    return bool(value)


def _three(value, what):
    """The three items of a 3-sequence with their names (``what[0]`` ...), or ``value`` three
    times named ``what`` if it is a single item."""
    if isinstance(value, (str, bytes)) or isinstance(value, (dict, set)):
        raise TypeError(f"{what}: a number or 3 numbers (x, y, z) are needed, got {_shown(value)}")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (numbers.Number, np.generic)):
        return ((value, what),) * 3
    try:
        items = tuple(itertools.islice(iter(value), 4))  # never more: an iterator may be endless
    except TypeError:
        raise TypeError(f"{what}: a number or 3 numbers (x, y, z) are needed, got {_shown(value)}") from None
    if len(items) != 3:
        got = "more than 3" if len(items) == 4 else str(len(items))
        raise ValueError(f"{what}: expected 3 values (x, y, z), got {got}")
    return tuple((v, f"{what}[{a}]") for a, v in enumerate(items))


def real_triple(value, what):
    """A real number or three, as three finite floats (DataError, a ValueError, for NaN or
    infinity, naming the axis)."""
    out = []
    for a, (v, label) in enumerate(_three(value, what)):
        out.append(real(v, label))
        if not math.isfinite(out[-1]):
            raise DataError(f"{label} ({'xyz'[a]}) = {out[-1]}: must be finite")
    return tuple(out)


_INT64 = range(-2**63, 2**63)


def integer_triple(value, what):
    """An integer or three, as three ints (floats refused, naming the item)."""
    if type(value) is tuple and len(value) == 3:  # the common case at once (a million domains' offsets)
        x, y, z = value
        if type(x) is int and type(y) is int and type(z) is int and x in _INT64 and y in _INT64 and z in _INT64:
            return value
    if type(value) is int and value in _INT64:
        return (value,) * 3
    return tuple(integer(v, label) for v, label in _three(value, what))


def _short(text):
    shown = repr(text)
    return shown if len(shown) <= 80 else shown[:77] + "..."


def text(value, what):
    """A str the C++ side reads as it is: no NUL (a C string would end there) and valid UTF-8
    (a lone surrogate, as Python decodes a byte of a file name that is not UTF-8, has no UTF-8
    form). ValueError naming ``what`` and the position (counted from 0)."""
    at = value.find("\0")
    if at >= 0:
        raise ValueError(f"{what}: {_short(value)} contains a NUL character at position {at}; "
                         f"it would cut the name there")
    try:
        value.encode("utf-8")
    except UnicodeEncodeError as e:
        raise ValueError(f"{what}: {_short(value)} is not valid UTF-8 text: {value[e.start]!r} at position "
                         f"{e.start} is a lone surrogate (what Python makes of a byte that is not UTF-8, "
                         f"e.g. in a file name); Tessera takes names and paths in UTF-8") from None
    return value


def name(value, what):
    """A non-empty str without NUL characters, in UTF-8 (a field or render name)."""
    if not isinstance(value, str):
        raise TypeError(f"{what}: a str is needed, got {_shown(value)}")
    if not value:
        raise ValueError(f"{what}: an empty name is not allowed (a field or render needs a name the config "
                         f"can refer to)")
    return text(value, what)


def path(value, what):
    """A file or directory name: a str or os.PathLike giving a str, without NUL characters,
    in UTF-8."""
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{what}: a path (str or os.PathLike) is needed, got {_shown(value)}")
    fs = os.fspath(value)
    if not isinstance(fs, str):
        raise TypeError(f"{what}: a str path is needed, got {_shown(fs)} from os.fspath")
    return text(fs, what)
