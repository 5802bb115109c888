"""Curvilinear and unstructured domains (tessera_mesh_domain, docs/python.md "Curvilinear and
unstructured meshes"): numpy arrays checked and described for the extension, read in place.

Everything the C side would read is checked here against the arrays that hold it (counts,
lengths, dtypes, layouts), so C never reads past an array; what only the values can tell (an
index out of range, an inverted element, NaN coordinates) is the adapter's check, on every
rank alike, naming the domain and element.
"""
import dataclasses

import numpy as np

from . import _checks
from ._arrays import ALLOWED, _DTYPES, DeviceArray, address_of, array_of, is_array

_FLOATS = {np.dtype(np.float32): 3, np.dtype(np.float64): 4}  # tessera_dtype of coordinates
_INDICES = {np.dtype(np.int32): 5, np.dtype(np.int64): 6}  # TESSERA_INT32, TESSERA_INT64
_UINT8 = 0
SHAPES = {"hex": (0, 8), "tet": (1, 4)}  # tessera_shape, vertices per element
NOT_YET_SHAPES = ("wedge", "pyramid")
_ASSOC = {"vertex": 0, "cell": 1}
_KEYS = ("coords", "fields", "dims", "shape", "connectivity", "association", "associations", "ghost_field")


@dataclasses.dataclass
class MeshDomain:
    """One curvilinear or unstructured domain of this rank (a dict with the same keys works
    too). coords: an (n, 3) array or three arrays x, y, z (float32 or float64, read in place);
    curvilinear: ``dims`` (vertices along i, j, k; i fastest in the coordinates); unstructured:
    ``shape`` ('hex' or 'tet') and ``connectivity`` (int32 or int64, (ncells, 8 | 4) or flat,
    0-based vertex indices in VTK's order); fields: ``{name: array}``; association: 'vertex' or
    'cell' for every field, or per field in ``associations``; ghost_field: the name of a uint8
    cell field marking ghost cells (nonzero)."""
    coords: object
    fields: dict
    dims: object = None
    shape: str = None
    connectivity: object = None
    association: str = "vertex"
    associations: dict = None
    ghost_field: str = None


def _plain(value, what, kinds, device=False):
    """``value`` as a numpy array of one of the dtypes ``kinds`` (names listed on refusal), never
    converted: anything else is a TypeError naming ``what``. ``device``: a CUDA array (by its
    protocol, _arrays.array_of) is accepted too, as a DeviceArray (the adapter copies a mesh's
    device arrays to the host, where it checks the elements and builds its tables)."""
    if isinstance(value, np.ma.MaskedArray):
        raise TypeError(f"{what}: a numpy masked array is not accepted (the values under its mask would be "
                        f"read); pass a.filled(value), or a.data")
    if device and not isinstance(value, np.ndarray) and is_array(value):
        value = array_of(value, what)
    if not isinstance(value, (np.ndarray, DeviceArray) if device else np.ndarray):
        raise TypeError(f"{what}: a numpy array is needed (read in place), got {type(value).__name__}")
    if value.dtype not in kinds:
        shown = value.dtype.name if value.dtype.isnative else value.dtype.str
        allowed = ", ".join(d.name for d in kinds)
        raise TypeError(f"{what}: dtype {shown} is not supported; allowed: {allowed} (native byte order)")
    if value.size == 0:
        raise ValueError(f"{what}: an empty array of shape {value.shape}")
    if not value.flags["ALIGNED"]:
        raise ValueError(f"{what}: unaligned memory (np.require(a, requirements='A') copies it)")
    return value


def _dense_ijk(a):
    """The element stride of a 3-D array [i, j, k] whose elements follow one another i, then j,
    then k, at one stride (a Fortran-ordered array, or the .T of a C-ordered (nk, nj, ni) one);
    None otherwise."""
    s = a.strides
    if s[1] == a.shape[0] * s[0] and s[2] == a.shape[1] * s[1]:
        return s[0]
    return None


def _coords(value, what):
    """(held arrays, (x, y, z addresses, dtype code, byte stride, count), vertex shape or None)."""
    if is_array(value) and not isinstance(value, (list, tuple, np.ma.MaskedArray)):
        a = _plain(value, what, _FLOATS, device=True)
        if a.ndim != 2 or a.shape[1] != 3:
            raise ValueError(f"{what}: an (n, 3) array (one row per vertex) or three arrays x, y, z are needed, "
                             f"got shape {a.shape}")
        base = address_of(a)
        return [a], (base, base + a.strides[1], base + 2 * a.strides[1], _FLOATS[a.dtype], a.strides[0],
                     a.shape[0]), None
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise TypeError(f"{what}: an (n, 3) array or a list of three arrays x, y, z is needed, got "
                        f"{_checks._shown(value) if not isinstance(value, (list, tuple)) else f'{len(value)} items'}")
    out, layout = [], None
    for axis, v in zip("xyz", value):
        label = f"{what}[{'xyz'.index(axis)}] ({axis})"
        a = _plain(v, label, _FLOATS, device=True)
        if a.ndim == 1:
            this = (a.dtype, a.strides[0], a.shape[0], None)
        elif a.ndim == 3 and _dense_ijk(a) is not None:
            this = (a.dtype, _dense_ijk(a), a.size, a.shape)
        else:
            raise ValueError(f"{label}: a 1-D array, or a 3-D array [i, j, k] whose vertices follow one another "
                             f"i fastest (np.asfortranarray, or the .T of a C-ordered (nk, nj, ni) array), is "
                             f"needed, got shape {a.shape} and strides {a.strides}")
        if layout is not None and this != layout:
            names = ("dtype", "byte stride", "number of vertices", "shape")
            which = next(n for n, p, q in zip(names, this, layout) if p != q)
            raise ValueError(f"{label}: its {which} ({this[names.index(which)]}) differs from x's "
                             f"({layout[names.index(which)]}): x, y and z are read with one dtype and one byte "
                             f"stride (tessera_coordset); an (n, 3) array always qualifies")
        layout = this
        out.append(a)
    addresses = tuple(address_of(a) for a in out)
    return out, addresses + (_FLOATS[layout[0]], layout[1], layout[2]), layout[3]


def _connectivity(value, what, shape):
    """(array, address, index dtype code, ncells) of an element list of ``shape``."""
    k = SHAPES[shape][1]
    a = _plain(value, what, _INDICES, device=True)
    if not (a.ndim == 2 and a.shape[1] == k) and not (a.ndim == 1 and a.shape[0] % k == 0):
        raise ValueError(f"{what}: {k} vertex indices per {shape} are needed, as an (ncells, {k}) array or a flat "
                         f"one of a multiple of {k}, got shape {a.shape}")
    if not a.flags["C_CONTIGUOUS"]:
        raise ValueError(f"{what}: a C-contiguous array is needed (the indices are read as ncells x {k} "
                         f"consecutive values); np.ascontiguousarray(c) copies it")
    return a, address_of(a), _INDICES[a.dtype], a.size // k


def _field(value, what, count, grid, words):
    """The binding's field tuple of one array with ``count`` values (one per ``words``): a 1-D
    array of any stride, or, on a curvilinear domain (``grid``: its i, j, k extent), a 3-D array
    [i, j, k] whose values follow one another i, then j, then k."""
    a = _plain(value, what, _DTYPES, device=True)
    if a.ndim == 1 and a.shape[0] == count:
        s = a.strides[0]
        return a, (s, s * count, s * count), (count, 1, 1)
    if grid is not None and a.ndim == 3 and a.shape == tuple(grid):
        s = _dense_ijk(a)
        if s is None:
            raise ValueError(f"{what}: a 3-D array [i, j, k] must hold its values i fastest, then j, then k "
                             f"(np.asfortranarray, or the .T of a C-ordered (nk, nj, ni) array), got strides "
                             f"{a.strides}; a 1-D array of any stride works too")
        return a, (s, s * grid[0], s * grid[0] * grid[1]), tuple(grid)
    shapes = f"a 1-D array of {count}" + (f" or a 3-D array of shape {tuple(grid)}" if grid is not None else "")
    raise ValueError(f"{what}: {count} values are needed, one per {words} ({shapes}), got shape {a.shape}")


def _get(dom, key, default=None):
    if isinstance(dom, dict):
        return dom.get(key, default)
    return getattr(dom, key, default)


def domain(where, dom):
    """(held arrays, the binding's domain tuple) of one domain, its faults named after ``where``."""
    if isinstance(dom, dict):
        unknown = [k for k in dom if k not in _KEYS]
        if unknown:
            raise ValueError(f"{where}: unknown keys {', '.join(map(repr, unknown))} (known: {', '.join(_KEYS)})")
        at = lambda key: f"{where}[{key!r}]"  # noqa: E731
    elif all(hasattr(dom, k) for k in ("coords", "fields")):
        at = lambda key: f"{where}.{key}"  # noqa: E731
    else:
        raise TypeError(f"{where}: a dict or a tessera.MeshDomain is needed, got {type(dom).__name__}")
    if _get(dom, "coords") is None:
        raise ValueError(f"{at('coords')} is missing: the vertex coordinates are needed")
    held, coords, coord_shape = _coords(_get(dom, "coords"), at("coords"))
    nverts = coords[-1]
    dims, shape, conn = _get(dom, "dims"), _get(dom, "shape"), _get(dom, "connectivity")
    if dims is not None and (shape is not None or conn is not None):
        raise ValueError(f"{where}: dims (curvilinear) and shape / connectivity (unstructured): give one kind")
    if dims is not None:  # curvilinear: a logical grid of vertices, i fastest
        dims = _checks.integer_triple(dims, at("dims"))
        if min(dims) < 2:
            raise ValueError(f"{at('dims')} = {dims}: at least 2 vertices along each axis are needed")
        if dims[0] * dims[1] * dims[2] != nverts or (coord_shape is not None and coord_shape != dims):
            raise ValueError(f"{at('coords')}: dims = {dims} needs {dims[0] * dims[1] * dims[2]} vertices"
                             f"{'' if coord_shape is None else f' (3-D arrays of shape {dims})'}, got {nverts}"
                             f"{'' if coord_shape is None else f' of shape {coord_shape}'}")
        ncells, cell_grid = (dims[0] - 1) * (dims[1] - 1) * (dims[2] - 1), tuple(n - 1 for n in dims)
        shape_code, conn_t = 0, (0, _INDICES[np.dtype(np.int64)], 0)
    else:
        if shape is None or conn is None:
            raise ValueError(f"{where}: dims (a curvilinear domain) or shape and connectivity (an unstructured "
                             f"one) are needed")
        if shape in NOT_YET_SHAPES:
            raise ValueError(f"{at('shape')} = {shape!r}: {shape} elements are not yet supported by Tessera "
                             f"('hex' and 'tet' are)")
        if not isinstance(shape, str) or shape not in SHAPES:
            raise ValueError(f"{at('shape')}: 'hex' or 'tet' is needed, got {_checks._shown(shape)}")
        if coord_shape is not None:
            raise ValueError(f"{at('coords')}: an unstructured domain's coordinates are 1-D (one value per vertex)")
        c, address, index_code, ncells = _connectivity(conn, at("connectivity"), shape)
        held.append(c)
        dims, cell_grid, shape_code, conn_t = (0, 0, 0), None, SHAPES[shape][0], (address, index_code, ncells)
    vertex_grid = dims if cell_grid is not None else None
    fields = _get(dom, "fields")
    if not isinstance(fields, dict):
        raise TypeError(f"{at('fields')}: a dict {{name: array}} is needed, got {_checks._shown(fields)}")
    ghost = _get(dom, "ghost_field")
    if ghost is not None:
        ghost = _checks.name(ghost, at("ghost_field"))
        if ghost not in fields:
            raise ValueError(f"{at('ghost_field')} = {ghost!r}: not one of the domain's fields")
    association, per_field = _associations(dom, fields, ghost, at)
    descs = []
    for name, array in fields.items():
        name = _checks.name(name, f"{at('fields')} key")
        cell = name == ghost or per_field.get(name, association) == "cell"
        what = f"{at('fields')}[{name!r}]"
        a, strides, shape3 = _field(array, what, ncells if cell else nverts, cell_grid if cell else vertex_grid,
                                    "cell" if cell else "vertex")
        if name == ghost and a.dtype != np.uint8:
            raise TypeError(f"{what}: the ghost field must be uint8 (nonzero = ghost), got {a.dtype.name}; "
                            f"(g != 0).astype(np.uint8) makes one")
        held.append(a)
        descs.append((name, address_of(a), _DTYPES[a.dtype], shape3, strides, (0, 0, 0),
                      (0, 0, 0)))
    return held, (_ASSOC[association], coords, dims, shape_code) + conn_t + (descs, ghost)


def _associations(dom, fields, ghost, at):
    """(the domain's association, {field: association} given per field), one association for
    every field but the ghost field (tessera_mesh_domain has one)."""
    association = _get(dom, "association", "vertex") or "vertex"
    if not isinstance(association, str) or association not in _ASSOC:
        raise ValueError(f"{at('association')}: 'vertex' or 'cell' is needed, got {_checks._shown(association)}")
    given = _get(dom, "associations") or {}
    if not isinstance(given, dict):
        raise TypeError(f"{at('associations')}: a dict {{field name: 'vertex' or 'cell'}} is needed")
    for name, a in given.items():
        if name not in fields:
            raise ValueError(f"{at('associations')}: {name!r} is not one of the domain's fields")
        if not isinstance(a, str) or a not in _ASSOC:
            raise ValueError(f"{at('associations')}[{name!r}]: 'vertex' or 'cell' is needed, got {_checks._shown(a)}")
        if name == ghost and a != "cell":
            raise ValueError(f"{at('associations')}[{name!r}] = {a!r}: the ghost field is cell data")
    used = {given.get(n, association) for n in fields if n != ghost}
    if len(used) > 1:
        raise ValueError(f"{at('associations')}: vertex and cell fields in one curvilinear or unstructured domain "
                         f"are not yet supported by Tessera (one association per domain)")
    return (used.pop() if used else association), given


def blocks(domains):
    """(arrays held, the binding's domain tuples) of a list of domains."""
    if not isinstance(domains, (list, tuple)):
        raise TypeError(f"domains: a list of dicts or tessera.MeshDomain is needed, got {type(domains).__name__}")
    held, out = [], []
    for d, dom in enumerate(domains):
        h, t = domain(f"domains[{d}]", dom)
        held += h
        out.append(t)
    return held, out


__all__ = ["MeshDomain", "blocks", "domain", "ALLOWED"]
