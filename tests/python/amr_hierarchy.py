"""A two-level hierarchy for the AMR tests (test_amr.py, mpi_amr_run.py): level 0 the conftest
field's (20, 16, 12) vertices, level 1 a box refined by 2 that holds the same smooth function
with finer detail, cut into patches."""
import copy

import numpy as np

from test_adapter import CONFIG, GRID

DIMS0 = (20, 16, 12)
RATIO = 2
# Level 1 covers level-0 vertices [6, 14] x [4, 12] x [3, 9]: level-1 vertices from BOX_LO, BOX_N of them
BOX_LO = (12, 8, 6)
BOX_N = (17, 17, 13)
AMR_CONFIG = copy.deepcopy(CONFIG)
AMR_CONFIG["renders"][0]["transfer_function"]["range"] = [-1.2, 2.2]
# Independent streams: at 4 spp the fine level's detail changes one sample of one pixel on
# these draws (test_amr's "the fine level shows"); the Sobol' sampler's draws miss it
AMR_CONFIG["renders"][0]["integrator"]["sampler"] = "independent"


def smooth(u, v, w):
    """The function both levels sample, at level-0 index positions (u, v, w), plus a detail
    that only level 1 resolves (zero on level-0 vertices)."""
    detail = 0.3 * np.sin(np.pi * u) ** 2 * np.sin(np.pi * v) ** 2
    return np.sin(u / 3.0) * np.cos(v / 4.0) + w / DIMS0[2] + detail


def level(l, lo=(0, 0, 0), n=None, fn=smooth):
    """Level l's vertices [lo, lo + n) as an array u[i, j, k] (float64)."""
    scale = RATIO ** l
    n = DIMS0 if n is None else n
    axes = [(lo[a] + np.arange(n[a])) / scale for a in range(3)]
    u, v, w = np.meshgrid(*axes, indexing="ij")
    return np.ascontiguousarray(fn(u, v, w).astype(np.float64))


def whole(fn=smooth, lo=BOX_LO, n=BOX_N, fine_offset=0.0):
    """The hierarchy as two domains (one per level); level 1 covers level-1 vertices
    [lo, lo + n) and holds fn + fine_offset."""
    return [{"fields": {"temperature": level(0, fn=fn)}},
            {"fields": {"temperature": level(1, lo, n, fn=fn) + fine_offset}, "offset": lo, "level": 1}]


def patches(fn=smooth):
    """The same hierarchy cut into 7 patches: level 0 in 3 slabs along k, level 1 in 4 pieces
    along i (uneven)."""
    out = []
    for k0, k1 in ((0, 5), (5, 6), (6, 12)):
        out.append({"fields": {"temperature": level(0, (0, 0, k0), (20, 16, k1 - k0), fn=fn)}, "offset": (0, 0, k0)})
    cuts = (0, 3, 9, 10, BOX_N[0])
    for c0, c1 in zip(cuts[:-1], cuts[1:]):
        lo = (BOX_LO[0] + c0, BOX_LO[1], BOX_LO[2])
        out.append({"fields": {"temperature": level(1, lo, (c1 - c0, BOX_N[1], BOX_N[2]), fn=fn)}, "offset": lo,
                    "level": 1})
    return out


MESH = dict(global_dims=DIMS0, nlevels=2, refinement=[RATIO], **GRID)
