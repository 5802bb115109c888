"""Run by test_adapter.py under mpirun -n 1 and -n 2: the conftest field split along k across
the ranks of an mpi4py communicator, each rank's block with one ghost layer (NaN where there is
no neighbour), published through tessera.Adapter. Rank 0 saves the image to argv[1].
argv[3] "domains": the field as cell data on a stretched y axis, cut into test_adapter's five
uneven domains dealt round robin over the ranks (zero-copy views, every other one Fortran
ordered), rendered replicated and distributed; rank 0 saves both images."""
import copy
import sys

import numpy as np
from mpi4py import MPI

import tessera
from conftest import field
from test_adapter import CONFIG, DOMAIN_CUTS, GRID, stretched_y

comm = MPI.COMM_WORLD
data = field().T.astype(np.float64)  # (nx, ny, nz): vertex (i, j, k)
nz = data.shape[2]
lo = nz * comm.rank // comm.size
hi = nz * (comm.rank + 1) // comm.size
# The block with one ghost layer on every side, ghosts from the neighbours (NaN outside)
block = np.full((data.shape[0] + 2, data.shape[1] + 2, hi - lo + 2), np.nan)
block[1:-1, 1:-1, 1:-1] = data[:, :, lo:hi]
if lo > 0:
    block[1:-1, 1:-1, 0] = data[:, :, lo - 1]
if hi < nz:
    block[1:-1, 1:-1, -1] = data[:, :, hi]
if len(sys.argv) > 3 and sys.argv[3] == "bad-array-on-last-rank":
    # The last rank passes an array it cannot describe (int32): it raises TypeError, the others
    # get a failed render (on_error: warn), and nobody waits forever in the collective.
    import warnings
    bad = comm.rank == comm.size - 1
    with tessera.Adapter(CONFIG, comm, output_dir=sys.argv[2], quiet=True) as viz:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", tessera.TesseraWarning)
            try:
                viz.execute(0, 0.0, {"temperature": block.astype(np.int32) if bad else block},
                            global_dims=data.shape, offset=(0, 0, lo), ghosts=1)
                assert not bad and viz.last_status != 0, "the render should fail on every rank"
                # ... with the refusing rank's reason (tessera_execute_refused), not a guess
                assert f"rank {comm.size - 1}" in viz.last_error and "int32" in viz.last_error, viz.last_error
            except TypeError as e:
                assert bad and "int32" in str(e), e
        # The next step works again on every rank
        viz.execute(2, 0.0, {"temperature": block}, global_dims=data.shape, offset=(0, 0, lo), ghosts=1)
        assert viz.last_status == 0, viz.last_error
    if comm.rank == 0:
        np.save(sys.argv[1], np.zeros(1))
    sys.exit(0)

if len(sys.argv) > 3 and sys.argv[3] == "refused-open":
    # The last rank refuses what it is given (a config, a path, an argument) while the others
    # accept theirs: every rank raises from the constructor (the others the same class, naming
    # the rank), none waits forever in the collective open; an adapter opens normally after.
    import os
    last = comm.rank == comm.size - 1
    good = dict(CONFIG, tessera=dict(CONFIG["tessera"], output_dir=sys.argv[2]))
    cases = [  # (what every rank raises, key path of the ConfigError, config, keyword arguments)
        (tessera.ConfigError, "tessera.colour", dict(good, tessera=dict(good["tessera"], colour="red")) if last else good,
         {}),
        (tessera.ConfigError, "", os.path.join(sys.argv[2], "missing.yaml") if last else good, {}),
        (TypeError, None, good, {"quiet": "no" if last else True}),
        (ValueError, None, good, {"output_dir": sys.argv[2] + ("\0" if last else "")}),
        (ValueError, None, good, {"output_dir": sys.argv[2] + ("\udcff" if last else "")}),
    ]
    for kind, key_path, config, kw in cases:
        try:
            tessera.Adapter(config, comm, **kw)
        except kind as e:
            assert last or f"rank {comm.size - 1} of {comm.size} refused" in str(e), e
            assert key_path is None or e.key_path == key_path, e.key_path  # the refusing rank's key path
        else:
            raise AssertionError(f"rank {comm.rank}: {kind.__name__} expected")
    with tessera.Adapter(good, comm, quiet=True) as viz:
        viz.execute(2, 0.0, {"temperature": block}, global_dims=data.shape, offset=(0, 0, lo), ghosts=1)
        assert viz.last_status == 0, viz.last_error
    if comm.rank == 0:
        np.save(sys.argv[1], np.zeros(1))
    sys.exit(0)

if len(sys.argv) > 3 and sys.argv[3] == "finalized":
    # MPI finalized: a communicator cannot be used any more; the adapter says so (RenderError)
    # instead of a call into MPI aborting the process. An adapter opened before is closed.
    viz = tessera.Adapter(CONFIG, comm, output_dir=sys.argv[2], quiet=True)
    rank = comm.rank
    MPI.Finalize()
    for call in (lambda: tessera.Adapter(CONFIG, comm, output_dir=sys.argv[2]),
                 lambda: viz.execute(2, 0.0, {"temperature": block}, global_dims=data.shape, offset=(0, 0, lo),
                                     ghosts=1)):
        try:
            call()
        except tessera.RenderError as e:
            assert "MPI is finalized" in str(e), e
        else:
            raise AssertionError("RenderError expected")
    viz.close()
    if rank == 0:
        np.save(sys.argv[1], np.zeros(1))
    sys.exit(0)

if len(sys.argv) > 3 and sys.argv[3] == "domains":
    mine = []
    for n, ((i, j, k), (a, b, c)) in enumerate(DOMAIN_CUTS):
        if n % comm.size == comm.rank:
            view = data[i:i + a, j:j + b, k:k + c]
            mine.append({"fields": {"temperature": np.asfortranarray(view) if n % 2 else view},
                         "offset": (i, j, k)})
    images = []
    for mode in ("replicated", "distributed"):
        config = copy.deepcopy(CONFIG)
        config["tessera"]["distribution"] = mode
        with tessera.Adapter(config, comm, output_dir=sys.argv[2], quiet=True) as viz:
            out = viz.execute(0, 0.0, domains=mine, global_dims=data.shape, association="cell",
                              coords=(None, stretched_y(data.shape[1]), None), **GRID)
            assert viz.last_status == 0, viz.last_error
        images.append(out.get("main"))
    if comm.rank == 0:
        np.save(sys.argv[1], np.stack(images))
    sys.exit(0)

with tessera.Adapter(CONFIG, comm, output_dir=sys.argv[2], quiet=True) as viz:
    images = viz.execute(0, 0.0, {"temperature": block}, spacing=(1.0, 1.5, 2.0), origin=(-3, 0, 1),
                         global_dims=data.shape, offset=(0, 0, lo), ghosts=1)
    assert viz.last_status == 0, viz.last_error
if comm.rank == 0:
    np.save(sys.argv[1], images["main"])
else:
    assert images == {}
