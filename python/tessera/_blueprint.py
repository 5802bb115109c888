"""Conduit Mesh Blueprint hierarchies as nested dicts of numpy arrays: Adapter.execute_blueprint.

A rank's domains are read here (each checked, every fault named by its path in the
hierarchy, e.g. ``mesh['fields']['energy']['association'] = 'face': ...``); how they fit
together (the global box, the offsets, the global axes) is _blueprint_layout's, from what
every rank read. Field values are read in place: a 1-D array (i fastest, as Blueprint lays
them out) or a (nk, nj, ni) array becomes a zero-copy [i, j, k] view.
"""
import math
import numbers

import numpy as np

from . import _checks, _mesh_domains
from ._arrays import DeviceArray, array_of, field_descriptor, is_array
from ._blueprint_layout import Summary, layout
from ._errors import ConfigError, DataError, DisabledError, OutputError, RenderError, TesseraError

NOT_YET = "not yet supported by Tessera"
GHOST_FIELDS = ("ascent_ghosts", "vtkGhostType")  # Ascent's and VTK's names of the ghost field
_ASSOCIATIONS = {"vertex": "vertex", "element": "cell"}
_MAX_DEPTH = 32  # deeper than any Blueprint hierarchy nests (a dict that contains itself stops here)
# The classes another rank's refusal is raised as, by name
_REFUSALS = {c.__name__: c for c in (TypeError, ValueError, ConfigError, DataError, RenderError, OutputError,
                                     DisabledError, TesseraError)}


def _at(path, key):
    return f"{path}[{key!r}]"


def _shown(value):
    """``'face'``, ``2.5``, ``list of 3 items``: what was given, short."""
    if isinstance(value, (str, numbers.Number)) and not isinstance(value, bool):
        text = repr(value) if not isinstance(value, np.generic) else repr(value.item())
        return text if len(text) <= 60 else text[:57] + "..."
    if isinstance(value, (np.ndarray, DeviceArray)):
        return f"an array of shape {value.shape} and dtype {value.dtype}"
    return f"a {type(value).__name__}"


# ---- The hierarchy as nested dicts ---------------------------------------------------------

def _merge(into, other, where):
    for key, value in other.items():
        old = into.get(key)
        if old is None:
            into[key] = value
        elif isinstance(old, dict) and isinstance(value, dict):
            _merge(old, value, _at(where, key))
        else:
            raise ValueError(f"{_at(where, key)} is given twice (as a path key 'a/b' and as a nested dict)")


def tree(node, path, depth=0):
    """``node`` as fresh nested dicts, Conduit's path keys (``"coordsets/coords/type"``)
    split into levels; leaves (arrays, numbers, text) are kept as they are, never copied."""
    if depth > _MAX_DEPTH:
        raise ValueError(f"{path}: nested deeper than {_MAX_DEPTH} levels (a dict that contains itself?)")
    out = {}
    for key, value in node.items():
        if not isinstance(key, str):
            raise TypeError(f"{path}: keys are str (Blueprint's names), got the key {_shown(key)}")
        parts = key.split("/")
        if "" in parts:
            raise ValueError(f"{_at(path, key)}: a path key with an empty part")
        cur, where = out, path
        for part in parts[:-1]:
            where = _at(where, part)
            cur = cur.setdefault(part, {})
            if not isinstance(cur, dict):
                raise ValueError(f"{where} is given twice (a value, and the parent of {key!r})")
        if isinstance(value, dict):
            value = tree(value, _at(where, parts[-1]), depth + 1)
        _merge(cur, {parts[-1]: value}, where)
    return out


def domains_of(mesh):
    """[(path, domain dict)] of a hierarchy: one domain (a dict with ``coordsets``), a list of
    domains, or a dict of named domains (Conduit's multi-domain object)."""
    if isinstance(mesh, (list, tuple)):
        out = []
        for d, dom in enumerate(mesh):
            if not isinstance(dom, dict):
                raise TypeError(f"mesh[{d}]: a domain (a dict with coordsets, topologies, fields) is needed, "
                                f"got {_shown(dom)}")
            out.append((f"mesh[{d}]", tree(dom, f"mesh[{d}]")))
        return out
    if not isinstance(mesh, dict):
        raise TypeError(f"mesh: a Blueprint hierarchy is needed (a dict with coordsets, topologies and fields, "
                        f"or a list or dict of such domains), got {_shown(mesh)}")
    root = tree(mesh, "mesh")
    if any(k in root for k in ("coordsets", "topologies", "fields", "state")):
        return [("mesh", root)]
    out = []
    for name, dom in root.items():
        if not isinstance(dom, dict):
            raise TypeError(f"{_at('mesh', name)} = {_shown(dom)}: a domain (a dict with coordsets, topologies, "
                            f"fields) is needed (mesh is neither one domain, having no 'coordsets', nor a dict "
                            f"of domains)")
        out.append((_at("mesh", name), dom))
    return out


def _need(node, key, path, kind, what):
    """node[key], a ``kind``; ValueError (missing) or TypeError naming the path and ``what``."""
    if key not in node:
        raise ValueError(f"{_at(path, key)} is missing: {what} is needed")
    value = node[key]
    if not isinstance(value, kind):
        raise TypeError(f"{_at(path, key)} = {_shown(value)}: {what} is needed")
    return value


def _choice(node, key, path, allowed, what):
    value = _need(node, key, path, str, what)
    if value not in allowed:
        raise ValueError(f"{_at(path, key)} = {value!r}: {what} is needed")
    return value


def _triple(node, path, names, what, default=None, check=None):
    """Three numbers ``node[names[a]]`` (a dict {x, y, z} or {i, j, k} ...)."""
    if node is None:
        return default
    if not isinstance(node, dict):
        raise TypeError(f"{path} = {_shown(node)}: a dict {{{', '.join(names)}}} of {what} is needed")
    out = []
    for name in names:
        if name not in node:
            raise ValueError(f"{_at(path, name)} is missing: Tessera renders 3D meshes, so "
                             f"{', '.join(names)} are needed")
        out.append(check(node[name], _at(path, name)))
    return tuple(out)


def _positive_int(value, what):
    v = _checks.integer(value, what)
    if v < 1:
        raise ValueError(f"{what} = {v}: at least 1 is needed")
    return v


def _finite(value, what):
    v = _checks.real(value, what)
    if not math.isfinite(v):
        raise DataError(f"{what} = {v}: a finite number is needed")
    return v


def _spacing(value, what):
    v = _finite(value, what)
    if v <= 0:
        raise DataError(f"{what} = {v}: a spacing > 0 is needed")
    return v


def _axis_values(value, what):
    """A rectilinear axis: a 1-D real array, finite and strictly increasing, as float64."""
    if not isinstance(value, np.ndarray) or isinstance(value, np.ma.MaskedArray):
        raise TypeError(f"{what} = {_shown(value)}: a 1-D numpy array of the axis' coordinates is needed")
    if value.ndim != 1 or value.shape[0] < 1 or value.dtype.kind not in "iuf":
        raise ValueError(f"{what} = {_shown(value)}: a 1-D array of real numbers (at least 1) is needed")
    c = np.asarray(value, dtype=np.float64)  # coordinates, not field values: a small copy at most
    bad = np.flatnonzero(~np.isfinite(c))
    if bad.size:
        raise DataError(f"{what}[{bad[0]}] = {c[bad[0]]}: coordinates must be finite")
    down = np.flatnonzero(np.diff(c) <= 0)
    if down.size:
        k = int(down[0])
        raise DataError(f"{what}[{k + 1}] = {c[k + 1]!r} after {c[k]!r}: coordinates must be strictly increasing")
    return c


def field_values(node, key, path):
    """node[key]: a field's values, a numpy or CUDA array (by its protocol, read in place) or a
    dict of component arrays; ValueError (missing) or TypeError naming the path."""
    values = _need(node, key, path, object, "a numpy array (or a dict of component arrays)")
    if not isinstance(values, dict) and not is_array(values):
        raise TypeError(f"{_at(path, key)} = {_shown(values)}: a numpy array (or a dict of component arrays; "
                        f"a CUDA array by __cuda_array_interface__ or DLPack) is needed")
    return values


def ghost_field_checks(fpath, fname, word, values):
    """A ghost field is element values in a numpy array: its values are looked at on the host."""
    if word != "element" or not isinstance(values, np.ndarray):
        if word == "element" and not isinstance(values, dict):  # a CUDA array
            raise DataError(f"{fpath}: a ghost field ({fname!r}) is read on the host: a numpy array is needed "
                            f"(cupy.asnumpy(g) copies one), got {_shown(values)}")
        raise DataError(f"{fpath}: a ghost field ({fname!r}) of element values is needed (vertex ghosts "
                        f"and components are {NOT_YET})")


def _view(values, shape, what, words, dtype_checked=True):
    """The zero-copy [i, j, k] view of a field's values: a 1-D array of the domain's elements
    in Blueprint's order (i fastest; any stride) or a numpy (nk, nj, ni) array; a CUDA array
    (_arrays.array_of) alike, as a DeviceArray view (its values never touched)."""
    if isinstance(values, np.ma.MaskedArray):
        raise TypeError(f"{what}: a numpy masked array is not accepted (the values under its mask would be "
                        f"rendered); pass a.filled(value), or a.data to render them all")
    if not isinstance(values, np.ndarray) and is_array(values):
        values = array_of(values, what)
    if not isinstance(values, (np.ndarray, DeviceArray)):
        raise TypeError(f"{what} = {_shown(values)}: a numpy array is needed (read in place; np.asarray(v) "
                        f"makes one)")
    ni, nj, nk = shape
    n = ni * nj * nk
    if values.ndim == 1 and values.shape[0] == n:
        s = values.strides[0]
        strides = (s, s * ni, s * ni * nj)
        view = (values.strided(shape, strides) if type(values) is DeviceArray else
                np.lib.stride_tricks.as_strided(values, shape=shape, strides=strides, writeable=False))
    elif values.ndim == 3 and values.shape == (nk, nj, ni):
        view = values.T
    else:
        raise ValueError(f"{what} = {_shown(values)}: {n} values are needed, one per {words} "
                         f"({ni} x {nj} x {nk}, i fastest), as a 1-D array or one of shape (nk, nj, ni) = "
                         f"({nk}, {nj}, {ni})")
    if dtype_checked:
        field_descriptor(view, what)  # the dtype, checked here (TypeError naming the path)
    return view


def _ghost_layers(flags, what):
    """(ghosts_lo, ghosts_hi) of a ghost field (element values, nonzero = ghost) whose ghost
    elements are whole layers at the domain's faces; DataError otherwise."""
    real = np.asarray(flags == 0)
    count = int(np.count_nonzero(real))
    if count == 0:
        raise DataError(f"{what}: every element is a ghost (nonzero): the domain has no real element")
    lo, hi = [], []
    for a in range(3):
        present = np.flatnonzero(real.any(axis=tuple(b for b in range(3) if b != a)))
        lo.append(int(present[0]))
        hi.append(int(real.shape[a] - 1 - present[-1]))
    box = tuple(slice(lo[a], real.shape[a] - hi[a]) for a in range(3))
    if count != real[box].size:
        raise DataError(f"{what}: the ghost elements (nonzero) are not whole layers at the domain's faces "
                        f"(the real ones span elements {lo} to {[real.shape[a] - 1 - hi[a] for a in range(3)]} "
                        f"but {real[box].size - count} ghost(s) lie inside that box): Tessera takes ghosts as "
                        f"layers at the faces ({NOT_YET} otherwise)")
    return tuple(lo), tuple(hi)


# ---- One domain ----------------------------------------------------------------------------

def _topology(node, path, topology):
    """(name, path, dict) of the topology to render."""
    topos = _need(node, "topologies", path, dict, "a dict of topologies {name: {type, coordset}}")
    tpath = _at(path, "topologies")
    if topology is None:
        if len(topos) != 1:
            names = ", ".join(map(repr, topos)) or "none"
            raise ValueError(f"{tpath}: one topology is needed (Tessera renders one per call), got {names}; "
                             f"pick one with execute_blueprint(..., topology=NAME)")
        topology = next(iter(topos))
    elif topology not in topos:
        raise ValueError(f"{tpath}: has no topology {topology!r} (topology=), only {', '.join(map(repr, topos))}")
    tpath = _at(tpath, topology)
    topo = topos[topology]
    if not isinstance(topo, dict):
        raise TypeError(f"{tpath} = {_shown(topo)}: a dict {{type, coordset}} is needed")
    return topology, tpath, topo, topos


def _coordset(node, path, topo, tpath):
    """(kind, vertex dims n, origin, spacing, axes) of the topology's coordinate set."""
    kind = _need(topo, "type", tpath, str, "'uniform', 'rectilinear', 'structured' or 'unstructured'")
    if kind == "points":
        raise DataError(f"{_at(tpath, 'type')} = {kind!r}: {kind} topologies are {NOT_YET} (uniform, "
                        f"rectilinear, structured and unstructured are)")
    if kind not in ("uniform", "rectilinear"):
        raise ValueError(f"{_at(tpath, 'type')} = {kind!r}: 'uniform', 'rectilinear', 'structured' or "
                         f"'unstructured' is needed (Blueprint's points are {NOT_YET})")
    name = _need(topo, "coordset", tpath, str, "the name of a coordinate set in coordsets")
    sets = _need(node, "coordsets", path, dict, "a dict of coordinate sets {name: {type, ...}}")
    cpath = _at(_at(path, "coordsets"), name)
    if name not in sets:
        raise ValueError(f"{_at(tpath, 'coordset')} = {name!r}: {_at(path, 'coordsets')} has no such coordinate "
                         f"set (it has {', '.join(map(repr, sets)) or 'none'})")
    cs = sets[name]
    if not isinstance(cs, dict):
        raise TypeError(f"{cpath} = {_shown(cs)}: a dict {{type, ...}} is needed")
    ctype = _need(cs, "type", cpath, str, f"'{kind}' (the topology's type)")
    if ctype != kind:
        raise ValueError(f"{_at(cpath, 'type')} = {ctype!r}: a {kind} topology needs a {kind!r} coordinate set"
                         + (" (explicit ones go with structured or unstructured topologies)"
                            if ctype == "explicit" else ""))
    if kind == "uniform":
        n = _triple(_need(cs, "dims", cpath, dict, "a dict {i, j, k} of vertex counts"), _at(cpath, "dims"),
                    "ijk", "vertex counts", check=_positive_int)
        origin = _triple(cs.get("origin"), _at(cpath, "origin"), "xyz", "numbers", (0.0, 0.0, 0.0), _finite)
        spacing = _triple(cs.get("spacing"), _at(cpath, "spacing"), ("dx", "dy", "dz"), "numbers", (1.0, 1.0, 1.0),
                          _spacing)
        return kind, n, origin, spacing, None, cpath
    values = _need(cs, "values", cpath, dict, "a dict {x, y, z} of coordinate arrays")
    axes = _triple(values, _at(cpath, "values"), "xyz", "coordinate arrays", check=_axis_values)
    return kind, tuple(len(c) for c in axes), None, None, axes, cpath


def _windows(node, path):
    """[(path, 'parent' | 'child', ratio)] of the domain's nesting-set windows (AMR)."""
    sets = node.get("nestsets")
    if sets is None:
        return []
    if not isinstance(sets, dict):
        raise TypeError(f"{_at(path, 'nestsets')} = {_shown(sets)}: a dict of nesting sets is needed")
    out = []
    for sname, nest in sets.items():
        spath = _at(_at(path, "nestsets"), sname)
        if not isinstance(nest, dict):
            raise TypeError(f"{spath} = {_shown(nest)}: a dict {{association, topology, windows}} is needed")
        windows = nest.get("windows", {})
        if not isinstance(windows, dict):
            raise TypeError(f"{_at(spath, 'windows')} = {_shown(windows)}: a dict of windows is needed")
        for wname, w in windows.items():
            wpath = _at(_at(spath, "windows"), wname)
            if not isinstance(w, dict):
                raise TypeError(f"{wpath} = {_shown(w)}: a dict {{domain_id, domain_type, ratio, ...}} is needed")
            kind = _choice(w, "domain_type", wpath, ("parent", "child"), "'parent' or 'child'")
            ratio = _triple(_need(w, "ratio", wpath, dict, "a dict {i, j, k}"), _at(wpath, "ratio"), "ijk",
                            "integer ratios", check=_positive_int)
            out.append((_at(wpath, "ratio"), kind, ratio))
    return out


def read_domain(path, node, topology, ghost_names):
    """(Summary, {field name: [i, j, k] view}, {field name: 'vertex' | 'cell'}) of one domain,
    every fault named by its path."""
    tname, tpath, topo, topos = _topology(node, path, topology)
    kind, n, origin, spacing, axes, cpath = _coordset(node, path, topo, tpath)
    state = node.get("state", {})
    if not isinstance(state, dict):
        raise TypeError(f"{_at(path, 'state')} = {_shown(state)}: a dict {{cycle, time, domain_id, ...}} is needed")
    level = 0
    if "level_id" in state:
        level = _checks.integer(state["level_id"], _at(_at(path, "state"), "level_id"), bits=32)
        if level < 0:
            raise ValueError(f"{_at(_at(path, 'state'), 'level_id')} = {level}: a level >= 0 is needed")
    fields = node.get("fields", {})
    if not isinstance(fields, dict):
        raise TypeError(f"{_at(path, 'fields')} = {_shown(fields)}: a dict {{name: field}} is needed")
    published, assoc, ghosts = {}, {}, None
    for fname, f in fields.items():
        fpath = _at(_at(path, "fields"), fname)
        if not isinstance(f, dict):
            raise TypeError(f"{fpath} = {_shown(f)}: a dict {{association, topology, values}} is needed")
        ftopo = _need(f, "topology", fpath, str, f"the name of its topology ({tname!r})")
        if ftopo != tname:
            if ftopo in topos:
                continue  # a field of another topology, not the one rendered (topology=)
            raise ValueError(f"{_at(fpath, 'topology')} = {ftopo!r}: {_at(path, 'topologies')} has no such "
                             f"topology (it has {', '.join(map(repr, topos))})")
        for key in ("grid_function", "basis", "matset", "matset_values"):
            if key in f:
                raise DataError(f"{_at(fpath, key)}: fields with a {key} are {NOT_YET} (association and values "
                                f"are)")
        word = _choice(f, "association", fpath, _ASSOCIATIONS, "'vertex' or 'element'")
        shape = n if word == "vertex" else tuple(m - 1 for m in n)
        if min(shape) < 1:
            raise DataError(f"{fpath}: element values on {n[0]} x {n[1]} x {n[2]} vertices: a domain with elements "
                            f"needs at least 2 vertices along each axis")
        values = field_values(f, "values", fpath)
        vpath = _at(fpath, "values")
        if fname in ghost_names:
            ghost_field_checks(fpath, fname, word, values)
            ghosts = _ghost_layers(_view(values, shape, vpath, "element", False), vpath)
            continue
        parts = values.items() if isinstance(values, dict) else [(None, values)]
        for comp, v in parts:  # Blueprint's mcarray: one scalar field per component, "name/component"
            name = fname if comp is None else f"{fname}/{comp}"
            published[_checks.name(name, f"{fpath} (its name)")] = _view(v, shape, vpath if comp is None else
                                                                         _at(vpath, comp), word)
            assoc[name] = _ASSOCIATIONS[word]
    glo, ghi = ghosts if ghosts is not None else ((0, 0, 0), (0, 0, 0))
    pieces = None if axes is None else tuple(axes[a][glo[a]:n[a] - ghi[a]] for a in range(3))
    summary = Summary(path, cpath, level, kind, tuple(sorted(set(assoc.values()))), n, glo, ghi, origin, spacing,
                      pieces, tuple(_windows(node, path)))
    return summary, published, assoc


# ---- The call ------------------------------------------------------------------------------

def _agree(comm, error, summaries):
    """Collective: every rank's summaries (what it read: a picklable value), once every rank
    has read its domains; when one rank could not, every rank raises (that rank its own
    error, the others the same class naming it)."""
    mine = None if error is None else (type(error).__name__, str(error))
    every = comm.allgather((mine, None if error is not None else summaries))
    if error is not None:
        raise error
    for rank, (refusal, _) in enumerate(every):
        if refusal is not None:
            cls = _REFUSALS.get(refusal[0], TesseraError)
            raise cls(f"rank {rank} of {len(every)} could not read its Blueprint hierarchy: {refusal[1]}")
    return [s for _, s in every]


def _execute_meshes(adapter, impl, step, step_i, time, final_b, meshes, every):
    """The call for structured and unstructured domains (every rank: the ranks agreed that some
    rank has such a domain); uniform or rectilinear domains beside them are refused alike."""
    grids = [(rank, len(s)) for rank, (s, _) in enumerate(every) if s]
    if grids:
        rank, n = grids[0]
        where = f" (rank {rank})" if len(every) > 1 else ""
        raise DataError(f"mesh: {n} uniform or rectilinear domain(s){where} beside structured or unstructured ones: "
                        f"one call renders one kind of topology ({NOT_YET} otherwise)")
    held = [a for h, _ in meshes for a in h]
    outcome = impl.execute_mesh_domains(step_i, float(time), [t for _, t in meshes], final_b,
                                        adapter._call_stream(held))
    del held  # the arrays were read in place during the call
    return adapter._outcome(outcome, step)


def execute(adapter, impl, step, time, mesh, final, topology, ghost_field_name):
    """Adapter.execute_blueprint (see there)."""
    from . import _blueprint_mesh  # it imports this module's helpers
    comm = adapter._comm
    error, summaries, fields, associations, meshes = None, [], [], [], []
    try:
        step_i, final_b = _checks.integer(step, "step"), _checks.flag(final, "final")
    except Exception as e:  # under MPI this rank still takes part, as Adapter.execute does
        if comm is None:
            raise
        error = e
        try:
            step_i, final_b = int(step), bool(final)
        except Exception:
            raise e from None
    if not impl.fires(step_i, final_b):  # nothing looked at: the C call returns at once, no rank communicates
        if error is not None:
            raise error
        return adapter.execute(step, time, domains=[], global_dims=(1, 1, 1), final=final)
    try:
        if error is not None:
            raise error
        _checks.real(time, "time")
        if topology is not None:
            topology = _checks.name(topology, "topology")
        names = (ghost_field_name,) if isinstance(ghost_field_name, str) else ghost_field_name
        if not isinstance(names, (list, tuple)):
            raise TypeError(f"ghost_field_name: a str or a list of str is needed, got {_shown(names)}")
        names = {_checks.name(g, f"ghost_field_name[{i}]") for i, g in enumerate(names)}
        for path, node in domains_of(mesh):
            if _blueprint_mesh.is_mesh(node, path, topology):  # explicit coordinates
                meshes.append(_mesh_domains.domain(path, _blueprint_mesh.read(path, node, topology, names)))
                continue
            summary, published, assoc = read_domain(path, node, topology, names)
            summaries.append(summary)
            fields.append(published)
            associations.append(assoc)
    except Exception as e:  # raised below on every rank, after the ranks agree
        error = e
    if comm is None:
        if error is not None:
            raise error
        every = [(summaries, len(meshes))]
    else:
        every = _agree(comm, error, (summaries, len(meshes)))
    if any(n for _, n in every):  # structured or unstructured topologies: tessera_execute_mesh_domains
        return _execute_meshes(adapter, impl, step, step_i, time, final_b, meshes, every)
    every = [s for s, _ in every]
    mesh_args, placements = layout(every)  # the same on every rank: all raise alike
    mesh_t = adapter._mesh(**mesh_args)
    blocks, held = [], []  # each field with its own ghosts: vertex fields leave shared faces to a neighbour
    for f, assoc, s, (off, lo, hi, vertex_hi) in zip(fields, associations, summaries,
                                                      placements[0 if comm is None else comm.rank]):
        descs = []
        for name, view in f.items():
            a, address, code, dims, strides = field_descriptor(view, name)
            held.append(a)
            descs.append((name, address, code, dims, strides, lo, vertex_hi if assoc[name] == "vertex" else hi))
        blocks.append((s.level, off, descs, [0 if assoc[name] == "vertex" else 1 for name in f]))
    outcome = impl.execute_domains(step_i, float(time), *mesh_t, blocks, final_b, adapter._call_stream(held))
    del held  # the arrays were read in place during the call
    return adapter._outcome(outcome, step)
