"""Checks of the public functions' arguments: a value of the wrong kind is refused with a
message naming the argument and what was given, never converted (no ``int(1.5)``, no
``float("2")``, no name cut at a NUL)."""
import math
import numbers
import os

import numpy as np

from ._errors import DataError


def _shown(value):
    """``float 1.5``, ``str '3'``: the type and a short repr of what was given."""
    text = str(value) if isinstance(value, np.generic) else repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    return f"{type(value).__name__} {text}"


def _is_bool(value):
    return isinstance(value, (bool, np.bool_))


def integer(value, what, bits=64):
    """``value`` as an int: a Python or numpy integer (not a bool) within the signed ``bits``
    range. TypeError for anything else (a float, even 2.0; a str), ValueError out of range."""
    if _is_bool(value) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{what}: an integer is needed, got {_shown(value)}")
    v = int(value)
    if not -2**(bits - 1) <= v < 2**(bits - 1):
        raise ValueError(f"{what}: {v} is outside the {bits}-bit range")
    return v


def real(value, what):
    """``value`` as a float: a Python or numpy real number (an int is one; a bool, str or
    complex is not: TypeError)."""
    if _is_bool(value) or not isinstance(value, numbers.Real):
        raise TypeError(f"{what}: a real number is needed, got {_shown(value)}")
    return float(value)


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
        items = tuple(value)
    except TypeError:
        raise TypeError(f"{what}: a number or 3 numbers (x, y, z) are needed, got {_shown(value)}") from None
    if len(items) != 3:
        raise ValueError(f"{what}: expected 3 values (x, y, z), got {len(items)}")
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


def integer_triple(value, what):
    """An integer or three, as three ints (floats refused, naming the item)."""
    return tuple(integer(v, label) for v, label in _three(value, what))


def _no_nul(text, what):
    at = text.find("\0")
    if at >= 0:
        raise ValueError(f"{what}: {text!r} contains a NUL character at position {at}; "
                         f"it would cut the name there")
    return text


def name(value, what):
    """A str without NUL characters (a field or render name)."""
    if not isinstance(value, str):
        raise TypeError(f"{what}: a str is needed, got {_shown(value)}")
    return _no_nul(value, what)


def path(value, what):
    """A file or directory name: a str or os.PathLike giving a str, without NUL characters."""
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{what}: a path (str or os.PathLike) is needed, got {_shown(value)}")
    text = os.fspath(value)
    if not isinstance(text, str):
        raise TypeError(f"{what}: a str path is needed, got {_shown(text)} from os.fspath")
    return _no_nul(text, what)
