"""Blueprint hierarchies (nested dicts) of the fields test_adapter renders, for test_blueprint.py
and mpi_blueprint_run.py: the same data as execute()/execute(domains=...) calls, so that both
paths can be compared bit for bit."""
import numpy as np

from test_adapter import DOMAIN_CUTS, GRID, stretched_y

ORIGIN, SPACING = GRID["origin"], GRID["spacing"]


def uniform(values, dims, origin=ORIGIN, spacing=SPACING, association="vertex", name="temperature", extra=None):
    """One domain: a uniform coordset of ``dims`` vertices, one field (``values``: [i, j, k]
    array, handed over as Blueprint's (nk, nj, ni) layout: a view, no copy)."""
    dom = {"coordsets": {"coords": {"type": "uniform", "dims": dict(zip("ijk", dims)),
                                    "origin": dict(zip("xyz", origin)),
                                    "spacing": dict(zip(("dx", "dy", "dz"), spacing))}},
           "topologies": {"topo": {"type": "uniform", "coordset": "coords"}},
           "fields": {name: {"association": association, "topology": "topo", "values": values.T}},
           "state": {"cycle": 0, "time": 0.0}}
    dom["fields"].update(extra or {})
    return dom


def ghost_field(shape, lo, hi):
    """Ascent's ghost field for elements of ``shape`` with lo/hi ghost layers: 1 ghost, 0 real."""
    g = np.ones(shape, dtype=np.int32)
    g[tuple(slice(lo[a], shape[a] - hi[a]) for a in range(3))] = 0
    return {"association": "element", "topology": "topo", "values": g.T.ravel()}


def padded(data, g, fill=1e30):
    out = np.full(tuple(n + 2 * g for n in data.shape), fill, dtype=data.dtype)
    out[g:-g, g:-g, g:-g] = data
    return out


def cell_domains(data, g=1, pick=lambda n: True):
    """DOMAIN_CUTS of a cell field data[i, j, k] as uniform Blueprint domains with ``g`` ghost
    layers on every face (junk values, marked by ascent_ghosts); every other one's values a
    flat strided view of a Fortran-ordered array."""
    big = padded(data, g)
    out = []
    for n, ((i, j, k), (a, b, c)) in enumerate(DOMAIN_CUTS):
        if not pick(n):
            continue
        block = big[i:i + a + 2 * g, j:j + b + 2 * g, k:k + c + 2 * g]
        if n % 2:
            block = np.asfortranarray(block)
        origin = tuple(ORIGIN[x] + ((i, j, k)[x] - g) * SPACING[x] for x in range(3))
        dom = uniform(block, (a + 2 * g + 1, b + 2 * g + 1, c + 2 * g + 1), origin, association="element",
                      extra={"ascent_ghosts": ghost_field(block.shape, (g,) * 3, (g,) * 3)})
        dom["state"]["domain_id"] = n
        out.append(dom)
    return out


def axes(nx, ny, nz):
    """The cell boundaries of the rectilinear test mesh: uniform x and z, stretched y."""
    return (ORIGIN[0] + np.arange(nx + 1) * SPACING[0], stretched_y(ny), ORIGIN[2] + np.arange(nz + 1) * SPACING[2])


def rectilinear_domains(data, g=1, pick=lambda n: True):
    """DOMAIN_CUTS of a cell field as rectilinear Blueprint domains, each with its own piece
    of the axes, ghost coordinates included (outside the mesh: made up, never used)."""
    glob = axes(*data.shape)
    ext = [np.concatenate([c[0] - np.arange(g, 0, -1), c, c[-1] + np.arange(1, g + 1)]) for c in glob]
    big = padded(data, g)
    out = []
    for n, ((i, j, k), (a, b, c)) in enumerate(DOMAIN_CUTS):
        if not pick(n):
            continue
        lo, size = (i, j, k), (a, b, c)
        block = big[i:i + a + 2 * g, j:j + b + 2 * g, k:k + c + 2 * g]
        values = {x: ext[d][lo[d]:lo[d] + size[d] + 2 * g + 1].copy() for d, x in enumerate("xyz")}
        out.append({"coordsets": {"coords": {"type": "rectilinear", "values": values}},
                    "topologies": {"topo": {"type": "rectilinear", "coordset": "coords"}},
                    "fields": {"temperature": {"association": "element", "topology": "topo",
                                               "values": np.ascontiguousarray(block.T).ravel()},
                               "ascent_ghosts": ghost_field(block.shape, (g,) * 3, (g,) * 3)}})
    return out


# Vertex data: the conftest field's (19, 15, 11) zones cut into boxes; each domain holds the
# vertices of its zones, sharing its face vertices with its neighbours as Blueprint does
ZONE_CUTS = [((0, 0, 0), (7, 15, 11)), ((7, 0, 0), (6, 8, 11)), ((7, 8, 0), (6, 7, 11)),
             ((13, 0, 0), (6, 15, 4)), ((13, 0, 4), (6, 15, 7))]


def vertex_domains(data, pick=lambda n: True):
    out = []
    for n, ((i, j, k), (a, b, c)) in enumerate(ZONE_CUTS):
        if pick(n):
            block = data[i:i + a + 1, j:j + b + 1, k:k + c + 1]
            origin = tuple(ORIGIN[x] + (i, j, k)[x] * SPACING[x] for x in range(3))
            out.append(uniform(block, block.shape, origin))
    return out


def mixed_domains(data, pick=lambda n: True):
    """vertex_domains with an element field "energy" too (half the vertex values at the cells'
    high corners), and that cell field as one array."""
    cells = np.ascontiguousarray(data[1:, 1:, 1:] * 0.5)
    out = vertex_domains(data, pick)
    for dom, ((i, j, k), (a, b, c)) in zip(out, [z for n, z in enumerate(ZONE_CUTS) if pick(n)]):
        dom["fields"]["energy"] = {"association": "element", "topology": "topo",
                                   "values": cells[i:i + a, j:j + b, k:k + c].T}
    return out, cells
