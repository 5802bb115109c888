"""Run by test_blueprint.py under mpirun -n 2: Blueprint domains dealt round robin over the
ranks of an mpi4py communicator and published with Adapter.execute_blueprint.
argv[3] "images": uniform cell domains with ghosts, rectilinear domains (each rank its own
pieces of the axes), vertex domains sharing faces, and those with an element field beside;
rank 0 saves the four images to argv[1].
argv[3] "refused": the last rank's hierarchy is malformed; every rank raises (the others
naming that rank), none waits forever, and the next call renders."""
import sys

import numpy as np
from mpi4py import MPI

import tessera
from blueprint_meshes import cell_domains, mixed_domains, rectilinear_domains, vertex_domains
from conftest import field
from test_adapter import CONFIG

comm = MPI.COMM_WORLD
data = field().T.astype(np.float64)
mine = lambda n: n % comm.size == comm.rank  # noqa: E731

if sys.argv[3] == "images":
    out = []
    with tessera.Adapter(CONFIG, comm, output_dir=sys.argv[2], quiet=True) as viz:
        for domains in (cell_domains(data, pick=mine), rectilinear_domains(data, pick=mine),
                        vertex_domains(data, pick=mine), mixed_domains(data, pick=mine)[0]):
            out.append(viz.execute_blueprint(0, 0.0, domains).get("main"))
            assert viz.last_status == 0, viz.last_error
    if comm.rank == 0:
        np.save(sys.argv[1], np.stack(out))
    else:
        assert out == [None] * 4

if sys.argv[3] == "refused":
    last = comm.rank == comm.size - 1
    with tessera.Adapter(CONFIG, comm, output_dir=sys.argv[2], quiet=True) as viz:
        domains = cell_domains(data, pick=mine)
        if last:
            domains[0]["fields"]["temperature"]["association"] = "face"
        try:
            viz.execute_blueprint(0, 0.0, domains)
        except ValueError as e:
            assert ("'face'" in str(e)) if last else f"rank {comm.size - 1} of {comm.size}" in str(e), e
        else:
            raise AssertionError("ValueError expected")
        # Ranks that disagree on the mesh (a spacing) all raise the same DataError
        domains = vertex_domains(data, pick=mine)
        if last:
            domains[0]["coordsets"]["coords"]["spacing"]["dx"] = 0.5
        try:
            viz.execute_blueprint(0, 0.0, domains)
        except tessera.DataError as e:
            assert "['spacing']['dx'] = 0.5" in str(e), e
        else:
            raise AssertionError("DataError expected")
        viz.execute_blueprint(2, 0.0, cell_domains(data, pick=mine))
        assert viz.last_status == 0, viz.last_error
    if comm.rank == 0:
        np.save(sys.argv[1], np.zeros(1))
