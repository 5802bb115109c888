"""Run by test_amr.py under mpirun -n 1 and -n 2: amr_hierarchy's seven patches dealt round
robin over the ranks of an mpi4py communicator, rendered by tessera.Adapter with two levels,
replicated and distributed; rank 0 saves both images to argv[1]."""
import copy
import sys

import numpy as np
from mpi4py import MPI

import tessera
from amr_hierarchy import AMR_CONFIG, MESH, patches

comm = MPI.COMM_WORLD
mine = [p for n, p in enumerate(patches()) if n % comm.size == comm.rank]
images = []
for mode in ("replicated", "distributed"):
    config = copy.deepcopy(AMR_CONFIG)
    config["tessera"]["distribution"] = mode
    with tessera.Adapter(config, comm, output_dir=sys.argv[2], quiet=True) as viz:
        images.append(viz.execute(0, 0.0, domains=mine, **MESH).get("main"))
        assert viz.last_status == 0, viz.last_error
if comm.rank == 0:
    np.save(sys.argv[1], np.stack(images))
