"""Blueprint's `explicit` coordinate sets with `structured` (curvilinear) or `unstructured`
(hex, tet) topologies: one domain of execute_blueprint read into the domain dict of
Adapter.execute_mesh_domains (_mesh_domains), every fault named by its path in the hierarchy.

Coordinates, connectivity and field values are read in place. The one copy: a ghost field
that is not uint8 (Ascent's ascent_ghosts is int32) becomes a uint8 mask, one byte per element.
"""
import numpy as np

from . import _checks
from ._arrays import DeviceArray, array_of, is_array
from ._blueprint import (NOT_YET, _at, _need, _positive_int, _shown, _topology, _triple, field_values,
                         ghost_field_checks)
from ._errors import DataError

MESH_TOPOLOGIES = ("structured", "unstructured")
_ASSOCIATIONS = {"vertex": "vertex", "element": "cell"}


def is_mesh(node, path, topology):
    """Whether the domain's topology to render is structured or unstructured."""
    _, _, topo, _ = _topology(node, path, topology)
    return topo.get("type") in MESH_TOPOLOGIES


def _explicit(node, path, topo, tpath, kind):
    """(coordinate values' path, [x, y, z]) of the topology's explicit coordinate set."""
    name = _need(topo, "coordset", tpath, str, "the name of a coordinate set in coordsets")
    sets = _need(node, "coordsets", path, dict, "a dict of coordinate sets {name: {type, ...}}")
    if name not in sets:
        raise ValueError(f"{_at(tpath, 'coordset')} = {name!r}: {_at(path, 'coordsets')} has no such coordinate "
                         f"set (it has {', '.join(map(repr, sets)) or 'none'})")
    cpath = _at(_at(path, "coordsets"), name)
    cs = sets[name]
    if not isinstance(cs, dict):
        raise TypeError(f"{cpath} = {_shown(cs)}: a dict {{type, values}} is needed")
    ctype = _need(cs, "type", cpath, str, "'explicit'")
    if ctype != "explicit":
        raise ValueError(f"{_at(cpath, 'type')} = {ctype!r}: {'an' if kind == 'unstructured' else 'a'} {kind} topology "
                         f"needs an 'explicit' coordinate set")
    values = _need(cs, "values", cpath, dict, "a dict {x, y, z} of coordinate arrays")
    vpath = _at(cpath, "values")
    xyz = _triple(values, vpath, "xyz", "coordinate arrays", check=lambda v, w: _array(v, w))
    return vpath, list(xyz)


def _array(value, what, device=False):
    """A numpy array; ``device``: a CUDA array too (field values), as a DeviceArray."""
    if device and not isinstance(value, np.ndarray) and is_array(value):
        value = array_of(value, what)
    if (not isinstance(value, (np.ndarray, DeviceArray) if device else np.ndarray)
            or isinstance(value, np.ma.MaskedArray)):
        raise TypeError(f"{what} = {_shown(value)}: a numpy array is needed (read in place)")
    return value


def _flat(values, n, what, words, grid, device=False):
    """A 1-D array of n values, or a structured domain's (nk, nj, ni) array as its [i, j, k]
    view (i fastest); ValueError naming the path otherwise. ``device``: field values, which may
    be a CUDA array."""
    values = _array(values, what, device)
    if values.ndim == 1 and values.shape[0] == n:
        return values
    if grid is not None and values.shape == tuple(reversed(grid)):
        return values.T
    extra = "" if grid is None else f" or one of shape (nk, nj, ni) = {tuple(reversed(grid))}"
    raise ValueError(f"{what} = {_shown(values)}: {n} values are needed, one per {words} (a 1-D array{extra})")


def read(path, node, topology, ghost_names):
    """The execute_mesh_domains domain dict of one Blueprint domain."""
    tname, tpath, topo, topos = _topology(node, path, topology)
    kind = topo["type"]
    vpath, xyz = _explicit(node, path, topo, tpath, kind)
    elements = _need(topo, "elements", tpath, dict, "a dict of the elements")
    epath = _at(tpath, "elements")
    dom = {}
    if kind == "structured":
        cells = _triple(_need(elements, "dims", epath, dict, "a dict {i, j, k} of element counts"),
                        _at(epath, "dims"), "ijk", "element counts", check=_positive_int)
        dom["dims"] = tuple(c + 1 for c in cells)
        grid_v, grid_c = dom["dims"], cells
        nverts = dom["dims"][0] * dom["dims"][1] * dom["dims"][2]
        ncells = cells[0] * cells[1] * cells[2]
    else:
        shape = _need(elements, "shape", epath, str, "'hex' or 'tet'")
        if shape not in ("hex", "tet"):
            raise DataError(f"{_at(epath, 'shape')} = {shape!r}: {shape} elements are {NOT_YET} ('hex' and 'tet' "
                            f"are)")
        conn = _array(_need(elements, "connectivity", epath, np.ndarray, "an array of vertex indices"),
                      _at(epath, "connectivity"))
        k = 8 if shape == "hex" else 4
        if conn.ndim != 1 or conn.shape[0] % k:
            raise ValueError(f"{_at(epath, 'connectivity')} = {_shown(conn)}: a 1-D array of {k} vertex indices per "
                             f"{shape} is needed")
        dom["shape"], dom["connectivity"] = shape, conn
        grid_v = grid_c = None
        nverts, ncells = None, conn.shape[0] // k
    xyz = [_flat(c, nverts, _at(vpath, a), "vertex", grid_v) if nverts is not None else c for c, a in zip(xyz, "xyz")]
    dom["coords"] = xyz
    nverts = xyz[0].size if nverts is None else nverts
    fields, assoc, ghost = _fields(node, path, tname, topos, ghost_names, nverts, ncells, grid_v, grid_c)
    used = set(assoc.values())
    if len(used) > 1:
        raise DataError(f"{_at(path, 'fields')}: vertex and element fields on one {kind} topology are {NOT_YET} "
                        f"(one association per domain)")
    dom["fields"], dom["association"] = fields, used.pop() if used else "vertex"
    if ghost is not None:
        dom["ghost_field"] = ghost
    return dom


def _fields(node, path, tname, topos, ghost_names, nverts, ncells, grid_v, grid_c):
    """({name: values}, {name: association}, ghost field name or None) of the domain."""
    fields = node.get("fields", {})
    if not isinstance(fields, dict):
        raise TypeError(f"{_at(path, 'fields')} = {_shown(fields)}: a dict {{name: field}} is needed")
    out, assoc, ghost = {}, {}, None
    for fname, f in fields.items():
        fpath = _at(_at(path, "fields"), fname)
        if not isinstance(f, dict):
            raise TypeError(f"{fpath} = {_shown(f)}: a dict {{association, topology, values}} is needed")
        ftopo = _need(f, "topology", fpath, str, f"the name of its topology ({tname!r})")
        if ftopo != tname:
            if ftopo in topos:
                continue
            raise ValueError(f"{_at(fpath, 'topology')} = {ftopo!r}: {_at(path, 'topologies')} has no such "
                             f"topology (it has {', '.join(map(repr, topos))})")
        for key in ("grid_function", "basis", "matset", "matset_values"):
            if key in f:
                raise DataError(f"{_at(fpath, key)}: fields with a {key} are {NOT_YET} (association and values "
                                f"are)")
        word = _need(f, "association", fpath, str, "'vertex' or 'element'")
        if word not in _ASSOCIATIONS:
            raise ValueError(f"{_at(fpath, 'association')} = {word!r}: 'vertex' or 'element' is needed")
        n, grid = (nverts, grid_v) if word == "vertex" else (ncells, grid_c)
        values = field_values(f, "values", fpath)
        vpath = _at(fpath, "values")
        if fname in ghost_names:
            ghost_field_checks(fpath, fname, word, values)
            flags = _flat(values, n, vpath, "element", grid)
            out[fname] = flags if flags.dtype == np.uint8 else (flags != 0).astype(np.uint8, order="F")
            ghost = fname
            continue
        parts = values.items() if isinstance(values, dict) else [(None, values)]
        for comp, v in parts:  # Blueprint's mcarray: one scalar field per component, "name/component"
            name = _checks.name(fname if comp is None else f"{fname}/{comp}", f"{fpath} (its name)")
            out[name] = _flat(v, n, vpath if comp is None else _at(vpath, comp), word, grid, device=True)
            assoc[name] = _ASSOCIATIONS[word]
    return out, assoc, ghost
