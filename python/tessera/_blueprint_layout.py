"""How the domains of a Blueprint hierarchy fit together: the global mesh (box, spacing or
axes, levels) and each domain's offset and ghost layers, from what every rank read.

Every rank runs this on the same summaries (gathered from all ranks), so every rank reaches
the same mesh or raises the same DataError: a collective decision without another message.
"""
import collections

import numpy as np

from ._errors import DataError

MAX_LEVELS = 8
_TOLERANCE = 1e-6  # how far (in elements) a domain's origin may lie from the grid: rounding only
_SPACING_TOLERANCE = 1e-9  # relative

# What a rank tells the others of one of its domains (picklable; association: the sorted
# associations of its fields, 'cell' and / or 'vertex'; real_axes: the coordinates of its real
# vertices, rectilinear only)
Summary = collections.namedtuple("Summary", "path cpath level kind association n ghosts_lo ghosts_hi origin spacing "
                                            "real_axes windows")


def _name(rank, s, nranks):
    return f"{s.path} (rank {rank})" if nranks > 1 else s.path


def _on(rank, nranks):
    return f" (rank {rank})" if nranks > 1 else ""


def _one_of(doms, attr, what, nranks):
    """The value of ``attr`` every domain that has one shares; DataError naming two that differ."""
    first = None
    for rank, s in doms:
        value = getattr(s, attr)
        if value is None:
            continue
        if first is None:
            first = (rank, s, value)
        elif value != first[2]:
            raise DataError(f"{what}: {_name(first[0], first[1], nranks)} has {first[2]!r} and "
                            f"{_name(rank, s, nranks)} has {value!r}; one call renders one kind "
                            f"(not yet supported by Tessera otherwise)")
    return None if first is None else first[2]


def _close(a, b):
    return abs(a - b) <= _SPACING_TOLERANCE * max(abs(a), abs(b))


def _levels(doms, nranks):
    """(nlevels, spacing of each level, refinement ratios) of uniform domains."""
    levels = sorted({s.level for _, s in doms})
    nlevels = levels[-1] + 1
    if nlevels > MAX_LEVELS:
        rank, s = next(d for d in doms if d[1].level == levels[-1])
        raise DataError(f"{s.path}['state']['level_id'] = {s.level}: at most {MAX_LEVELS} levels (0 .. "
                        f"{MAX_LEVELS - 1}) are supported")
    missing = [l for l in range(nlevels) if l not in levels]
    if missing:
        raise DataError(f"state/level_id: no domain on any rank is at level {missing[0]}, but some are at level "
                        f"{levels[-1]}: levels 0 .. {nlevels - 1} each need domains")
    spacing, ratios = [], []
    for l in range(nlevels):
        rank, s = next(d for d in doms if d[1].level == l)
        if l == 0:
            spacing.append(s.spacing)
            continue
        q = [spacing[l - 1][a] / s.spacing[a] for a in range(3)]
        r = round(q[0])
        if r not in (2, 4) or any(abs(x - r) > _TOLERANCE * r for x in q):
            raise DataError(f"{s.cpath}['spacing'] = {s.spacing} at level {l}{_on(rank, nranks)}: the "
                            f"spacing of level {l - 1} ({spacing[l - 1]}) divided by 2 or by 4, the same on every "
                            f"axis, is needed (the ratios are {q})")
        ratios.append(r)
        spacing.append(tuple(spacing[l - 1][a] / r for a in range(3)))
    for rank, s in doms:
        for a, name in enumerate(("dx", "dy", "dz")):
            if not _close(s.spacing[a], spacing[s.level][a]):
                raise DataError(f"{s.cpath}['spacing']['{name}'] = {s.spacing[a]!r}{_on(rank, nranks)}: "
                                f"every domain of level {s.level} needs the level's spacing "
                                f"{spacing[s.level][a]!r}")
    return nlevels, spacing, ratios


def _uniform(doms, nranks):
    """The mesh arguments and each domain's (offset, real count) of uniform domains."""
    nlevels, spacing, ratios = _levels(doms, nranks)
    first = [[s.origin[a] + s.ghosts_lo[a] * s.spacing[a] for a in range(3)] for _, s in doms]
    origin = tuple(min(p[a] for p, (_, s) in zip(first, doms) if s.level == 0) for a in range(3))
    placed = []
    for p, (rank, s) in zip(first, doms):
        offset = []
        for a, axis in enumerate("xyz"):
            x = (p[a] - origin[a]) / spacing[s.level][a]
            k = round(x)
            if abs(x - k) > _TOLERANCE:
                raise DataError(f"{s.cpath}['origin']['{axis}'] = {s.origin[a]!r}{_on(rank, nranks)}: the "
                                f"domain's first real vertex ({p[a]!r}) is not on the level-{s.level} grid of the "
                                f"mesh (origin {origin[a]!r}, spacing {spacing[s.level][a]!r}: {x:.6g} elements "
                                f"from the origin)")
            offset.append(k)
        placed.append(tuple(offset))
    return placed, dict(origin=origin, spacing=spacing[0], coords=None, nlevels=nlevels,
                        refinement=ratios or None)


def _rectilinear(doms, nranks):
    """The global axes assembled from the domains' pieces, and each domain's offset in them."""
    if any(s.level for _, s in doms):
        rank, s = next(d for d in doms if d[1].level)
        raise DataError(f"{s.path}['state']['level_id'] = {s.level}: refinement levels with a rectilinear "
                        f"coordinate set are not yet supported by Tessera (uniform ones are)")
    axes = [np.unique(np.concatenate([s.real_axes[a] for _, s in doms])) for a in range(3)]
    placed = []
    for rank, s in doms:
        offset = []
        for a, axis in enumerate("xyz"):
            piece = s.real_axes[a]
            at = int(np.searchsorted(axes[a], piece[0]))
            mine = axes[a][at:at + len(piece)]
            if not np.array_equal(mine, piece):  # a value another domain has lies inside this piece
                k = int(np.flatnonzero(mine != piece)[0])  # >= 1: the piece's first value is at `at`
                w = float(mine[k])
                r, o = next((r, o) for r, o in doms if np.any(o.real_axes[a] == w))
                m = o.ghosts_lo[a] + int(np.searchsorted(o.real_axes[a], w))
                raise DataError(f"{o.cpath}['values']['{axis}'][{m}] = {w!r}{_on(r, nranks)} lies between "
                                f"{s.cpath}['values']['{axis}'][{s.ghosts_lo[a] + k - 1}] = {float(piece[k - 1])!r} "
                                f"and [{s.ghosts_lo[a] + k}] = {float(piece[k])!r}{_on(rank, nranks)}: the "
                                f"domains' coordinates must agree where they meet (Tessera assembles one global "
                                f"{axis} axis from the domains' pieces)")
            offset.append(at)
        placed.append(tuple(offset))
    return placed, axes


def _shared_faces(doms, placed):
    """Vertex fields: the high face of a domain on which another domain of its level starts
    (Blueprint's neighbours share their face vertices) is that neighbour's, so that each vertex
    has one owner: per domain, 1 on each axis whose high vertex layer its vertex fields leave
    to the neighbour (as a ghost layer), else 0."""
    boxes = [(off, tuple(off[a] + s.n[a] - s.ghosts_lo[a] - s.ghosts_hi[a] - 1 for a in range(3)))
             for off, (_, s) in zip(placed, doms)]  # real vertices, inclusive
    lows = collections.defaultdict(list)
    for d, (lo, _) in enumerate(boxes):
        for a in range(3):
            lows[(doms[d][1].level, a, lo[a])].append(d)
    drops = []
    for d, (lo, hi) in enumerate(boxes):
        drop = [0, 0, 0]
        for a in range(3):
            for e in lows.get((doms[d][1].level, a, hi[a]), ()) if hi[a] > lo[a] else ():
                elo, ehi = boxes[e]
                if e != d and all(max(lo[b], elo[b]) < min(hi[b], ehi[b]) for b in range(3) if b != a):
                    drop[a] = 1
                    break
        drops.append(tuple(drop))
    return drops


def _windows(doms, ratios, nranks):
    """Blueprint's nesting windows, where given, agree with the ratios the spacings give."""
    for rank, s in doms:
        for path, kind, ratio in s.windows:
            level = s.level if kind == "child" else s.level - 1
            want = ratios[level] if 0 <= level < len(ratios) else None
            if ratio != (want,) * 3:
                raise DataError(f"{path} = {dict(zip('ijk', ratio))}{_on(rank, nranks)} (a {kind} window of a level-"
                                f"{s.level} domain): "
                                + (f"the spacings give the ratio {want} between levels {level} and {level + 1}"
                                   if want else f"there is no level {level + 1 if kind == 'child' else level}"))


def layout(ranks):
    """(keyword arguments of Adapter.execute describing the mesh, and per rank per domain
    (offset, ghosts_lo, ghosts_hi, ghosts_hi of its vertex fields)) from every rank's list of
    Summary."""
    nranks = len(ranks)
    doms = [(r, s) for r, sums in enumerate(ranks) for s in sums]
    if not doms:
        raise DataError("mesh: no rank published a domain (an empty hierarchy on every rank)")
    # A cell mesh where any field is element data (vertex fields then have one value more per
    # axis on the same cells); a vertex mesh where all are vertex data
    cell = any("cell" in s.association for _, s in doms)
    association = "cell" if cell else "vertex"
    kind = _one_of(doms, "kind", "coordinate set type", nranks)
    if kind == "uniform":
        placed, mesh = _uniform(doms, nranks)
    else:
        placed, axes = _rectilinear(doms, nranks)
        mesh = dict(origin=tuple(float(x[0]) for x in axes), spacing=1.0, coords=tuple(axes), nlevels=1,
                    refinement=None)
    # Real elements of each domain; the mesh's elements are level 0's extent
    counts = [tuple(s.n[a] - s.ghosts_lo[a] - s.ghosts_hi[a] - (1 if cell else 0) for a in range(3))
              for _, s in doms]
    mesh["global_dims"] = tuple(max(off[a] + c[a] for off, c, (_, s) in zip(placed, counts, doms) if s.level == 0)
                                for a in range(3))
    _windows(doms, mesh["refinement"] or [], nranks)
    drops = _shared_faces(doms, placed)
    out = [[] for _ in ranks]
    for (rank, s), off, drop in zip(doms, placed, drops):
        out[rank].append((off, s.ghosts_lo, s.ghosts_hi, tuple(s.ghosts_hi[a] + drop[a] for a in range(3))))
    mesh["association"] = association
    return mesh, out
