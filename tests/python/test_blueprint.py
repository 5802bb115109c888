"""Adapter.execute_blueprint: Conduit Mesh Blueprint hierarchies as nested dicts give the
images of the equivalent execute / execute(domains=...) calls, bit for bit (uniform vertex and
element data, rectilinear, several domains, refinement levels, 1 and 2 MPI ranks); malformed
hierarchies raise naming their path; nothing is looked at where no render fires."""
import copy
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

import tessera
from amr_hierarchy import MESH as AMR_MESH, AMR_CONFIG, patches
from blueprint_meshes import (ORIGIN, SPACING, axes, cell_domains, mixed_domains, rectilinear_domains,
                              uniform, vertex_domains)
from conftest import HERE, field, same_bits
from test_adapter import CONFIG, GRID


def images(tmp_path, config=CONFIG, **calls):
    """{label: main image} of one adapter's calls at step 0, each (method name, args, kwargs)."""
    out = {}
    with tessera.Adapter(config, output_dir=tmp_path, quiet=True) as viz:
        for label, (method, args, kw) in calls.items():
            out[label] = getattr(viz, method)(0, 0.0, *args, **kw)["main"]
            assert viz.last_status == 0, viz.last_error
    return out


def test_uniform_vertex_data_in_every_form_equals_execute(tmp_path):
    """One domain as nested dicts, as Conduit path keys, with flat or (nk, nj, ni) values, as a
    list and as a dict of domains: the image of execute(fields)."""
    data = field().T  # (20, 16, 12): u[i, j, k]
    nested = uniform(data, data.shape)
    flat = {"coordsets/coords/type": "uniform", "coordsets/coords/dims/i": 20, "coordsets/coords/dims/j": 16,
            "coordsets/coords/dims/k": 12, "coordsets/coords/origin": {"x": -3.0, "y": 0.0, "z": 1.0},
            "coordsets/coords/spacing/dx": 1.0, "coordsets/coords/spacing/dy": 1.5,
            "coordsets/coords/spacing/dz": 2.0, "topologies/topo/type": "uniform",
            "topologies/topo/coordset": "coords", "fields/temperature/association": "vertex",
            "fields/temperature/topology": "topo", "fields/temperature/values": field().ravel()}
    got = images(tmp_path, plain=("execute", ({"temperature": data},), GRID),
                 nested=("execute_blueprint", (nested,), {}), flat=("execute_blueprint", (flat,), {}),
                 listed=("execute_blueprint", ([nested],), {}),
                 named=("execute_blueprint", ({"domain_000000": flat},), {}))
    assert got["plain"][..., 3].max() > 0.1
    for label in ("nested", "flat", "listed", "named"):
        assert same_bits(got["plain"], got[label]), label


def test_element_data_in_domains_with_ghost_layers_equals_execute_domains(tmp_path):
    """Cell data cut into 5 uneven domains with a ghost layer on every face (junk values,
    marked by ascent_ghosts), half of them strided views of Fortran-ordered arrays."""
    data = field().T.astype(np.float64)
    mesh = dict(global_dims=data.shape, association="cell", **GRID)
    got = images(tmp_path, plain=("execute", (), dict(domains=[{"fields": {"temperature": data}}], **mesh)),
                 blueprint=("execute_blueprint", (cell_domains(data),), {}),
                 reversed=("execute_blueprint", (cell_domains(data)[::-1],), {}),
                 vtk=("execute_blueprint", (cell_domains(data),), {"ghost_field_name": "ascent_ghosts"}))
    for label in ("blueprint", "reversed", "vtk"):
        assert same_bits(got["plain"], got[label]), label


def test_vertex_domains_sharing_their_face_vertices_equal_execute(tmp_path):
    """Blueprint's neighbours both hold the vertices of the face they share; each is read once."""
    data = field().T
    got = images(tmp_path, plain=("execute", ({"temperature": data},), GRID),
                 blueprint=("execute_blueprint", (vertex_domains(data),), {}))
    assert same_bits(got["plain"], got["blueprint"])


def test_rectilinear_domains_assemble_the_global_axes(tmp_path):
    """Each domain brings its own piece of the axes (ghost coordinates included): the image of
    execute(domains) with the whole axes; pieces that disagree name the domain, axis and index."""
    data = field().T.astype(np.float64)
    mesh = dict(global_dims=data.shape, association="cell", coords=axes(*data.shape), **GRID)
    got = images(tmp_path, plain=("execute", (), dict(domains=[{"fields": {"temperature": data}}], **mesh)),
                 blueprint=("execute_blueprint", (rectilinear_domains(data),), {}))
    assert same_bits(got["plain"], got["blueprint"])
    bad = rectilinear_domains(data)
    bad[1]["coordsets"]["coords"]["values"]["y"][1] += 1e-9  # domain 1's first real y vertex
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        with pytest.raises(tessera.DataError, match=re.escape("mesh[1]['coordsets']['coords']['values']['y'][1]")):
            viz.execute_blueprint(0, 0.0, bad)


def test_refinement_levels_from_level_id_equal_execute_domains(tmp_path):
    """amr_hierarchy's 7 patches on 2 levels as Blueprint domains (state/level_id, a nesting set
    whose child windows say ratio 2): the image of execute(domains, nlevels=2)."""
    domains = []
    for p in patches():
        level = p.get("level", 0)
        h = tuple(s / 2 ** level for s in SPACING)
        origin = tuple(ORIGIN[a] + p.get("offset", (0, 0, 0))[a] * h[a] for a in range(3))
        dom = uniform(p["fields"]["temperature"], p["fields"]["temperature"].shape, origin, h)
        dom["state"]["level_id"] = level
        if level == 0:
            dom["nestsets/nest/windows/window_0"] = {"domain_id": 3, "domain_type": "child",
                                                     "ratio": {"i": 2, "j": 2, "k": 2}}
        domains.append(dom)
    got = images(tmp_path, AMR_CONFIG, plain=("execute", (), dict(domains=patches(), **AMR_MESH)),
                 blueprint=("execute_blueprint", (domains,), {}))
    assert same_bits(got["plain"], got["blueprint"])
    domains[0]["nestsets/nest/windows/window_0"]["ratio"]["k"] = 4
    with tessera.Adapter(AMR_CONFIG, output_dir=tmp_path, quiet=True) as viz:
        with pytest.raises(tessera.DataError, match="the spacings give the ratio 2"):
            viz.execute_blueprint(0, 0.0, domains)


def test_vector_components_and_a_chosen_topology(tmp_path):
    """A field with component arrays (an mcarray: strided views of one interleaved array) is
    published as one field per component, "velocity/u" ...; topology= picks one of several
    topologies, and the fields of the others are left out."""
    data = field().T
    inter = np.zeros(data.size * 3)
    inter[1::3] = data.T.ravel()  # component v of an interleaved (n, 3) array
    dom = uniform(data, data.shape, name="other")
    dom["topologies"]["points"] = {"type": "points", "coordset": "coords"}
    dom["fields"]["other"]["topology"] = "points"
    dom["fields"]["velocity"] = {"association": "vertex", "topology": "topo",
                                 "values": {"u": inter[0::3], "v": inter[1::3], "w": inter[2::3]}}
    config = copy.deepcopy(CONFIG)
    config["renders"][0]["field"] = "velocity/v"
    got = images(tmp_path, config, plain=("execute", ({"velocity/v": data},), GRID),
                 blueprint=("execute_blueprint", (dom,), {"topology": "topo"}))
    assert same_bits(got["plain"], got["blueprint"])


def test_vertex_and_element_fields_in_one_call(tmp_path):
    """A vertex field and an element field on one topology, in domains that share their face
    vertices: each renders as on its own mesh (the vertex field sampled on the cells' mesh)."""
    data = field().T  # (20, 16, 12) vertices, (19, 15, 11) cells
    domains, cells = mixed_domains(data)
    energy = copy.deepcopy(CONFIG)
    energy["renders"][0]["field"] = "energy"
    got = images(tmp_path, plain=("execute", ({"temperature": data},), GRID),
                 blueprint=("execute_blueprint", (domains,), {}))
    assert same_bits(got["plain"], got["blueprint"])
    mesh = dict(domains=[{"fields": {"energy": cells}}], global_dims=cells.shape, association="cell", **GRID)
    got = images(tmp_path, energy, plain=("execute", (), mesh), blueprint=("execute_blueprint", (domains,), {}))
    assert same_bits(got["plain"], got["blueprint"])


def test_nothing_is_looked_at_where_no_render_fires(tmp_path):
    class Untouchable(dict):
        def __getattribute__(self, name):
            raise AssertionError(f"the hierarchy was looked at ({name})")

    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:  # every: 2
        assert viz.execute_blueprint(1, 0.5, Untouchable()) == {}
        assert viz.last_status == 0 and viz.results == []


def _good():
    return uniform(field().T, (20, 16, 12))


def _set(path, value):
    """A change to _good(): path a tuple of keys, value None to delete."""
    def change(dom):
        node = dom
        for key in path[:-1]:
            node = node[key]
        if value is None:
            del node[path[-1]]
        else:
            node[path[-1]] = value(node[path[-1]]) if callable(value) else value
        return dom
    return change


T = "mesh['fields']['temperature']"
C = "mesh['coordsets']['coords']"
MALFORMED = [  # (change, exception, what the message says)
    (_set(("coordsets",), None), ValueError, "mesh['coordsets'] is missing"),
    (_set(("coordsets", "coords", "dims", "k"), None), ValueError, f"{C}['dims']['k'] is missing"),
    (_set(("coordsets", "coords", "dims", "i"), 20.0), TypeError, f"{C}['dims']['i']: an integer is needed"),
    (_set(("coordsets", "coords", "spacing", "dy"), -1.0), tessera.DataError, f"{C}['spacing']['dy'] = -1.0"),
    (_set(("coordsets", "coords", "type"), "explicit"), ValueError,
     f"{C}['type'] = 'explicit': a uniform topology needs a 'uniform' coordinate set (explicit ones go with"),
    (_set(("topologies", "topo", "type"), "structured"), ValueError,
     f"{C}['type'] = 'uniform': a structured topology needs an 'explicit' coordinate set"),
    (_set(("topologies", "topo", "type"), "unstructured"), ValueError, "an unstructured topology needs an 'explicit'"),
    (_set(("topologies", "topo", "type"), "points"), tessera.DataError, "points topologies are not yet supported"),
    (_set(("topologies", "topo", "coordset"), "xyz"), ValueError, "'xyz': mesh['coordsets'] has no such"),
    (_set(("topologies", "extra"), {"type": "uniform", "coordset": "coords"}), ValueError,
     "mesh['topologies']: one topology is needed (Tessera renders one per call), got 'topo', 'extra'"),
    (_set(("fields", "temperature", "association"), "face"), ValueError,
     f"{T}['association'] = 'face': 'vertex' or 'element' is needed"),
    (_set(("fields", "temperature", "association"), 3), TypeError, f"{T}['association'] = 3"),
    (_set(("fields", "temperature", "topology"), "mesh"), ValueError, f"{T}['topology'] = 'mesh': mesh['topologies'] "
                                                                      f"has no such topology"),
    (_set(("fields", "temperature", "values"), None), ValueError, f"{T}['values'] is missing"),
    (_set(("fields", "temperature", "values"), lambda v: v.ravel()[:-1]), ValueError,
     f"{T}['values'] = an array of shape (3839,) and dtype float32: 3840 values are needed"),
    (_set(("fields", "temperature", "values"), lambda v: v.T), ValueError, "of shape (nk, nj, ni) = (12, 16, 20)"),
    (_set(("fields", "temperature", "values"), lambda v: v.astype(np.int64)), TypeError,
     f"{T}['values']: dtype int64 is not supported"),
    (_set(("fields", "temperature", "values"), lambda v: v.ravel().tolist()), TypeError,
     f"{T}['values'] = a list: a numpy array (or a dict"),
    (_set(("fields", "temperature", "association"), "element"), ValueError,
     "3135 values are needed, one per element (19 x 15 x 11, i fastest)"),
    (_set(("fields", "energy"), {"association": "element", "topology": "topo", "values": {"u": np.zeros(3135),
                                                                                        "v": [0.0]}}),
     TypeError, f"mesh['fields']['energy']['values']['v'] = a list: a numpy array is needed"),
    (_set(("fields", "ascent_ghosts"), {"association": "element", "topology": "topo",
                                        "values": np.eye(1, 3135, 1000, dtype=np.int32).ravel()}),
     tessera.DataError, "['ascent_ghosts']['values']: the ghost elements (nonzero) are not whole layers"),
    (_set(("fields", "temperature", "matset"), "mat"), tessera.DataError, "fields with a matset are not yet"),
    (_set(("state",), [0]), TypeError, "mesh['state'] = a list"),
    (lambda dom: dict(dom, **{"fields/temperature/association": "vertex"}), ValueError, "is given twice"),
    (lambda dom: 7, TypeError, "mesh: a Blueprint hierarchy is needed"),
    (lambda dom: [dom, 7], TypeError, "mesh[1]: a domain"),
    (lambda dom: [dom, _set(("coordsets", "coords", "origin", "x"), -2.5)(_good())], tessera.DataError,
     f"mesh[1]['coordsets']['coords']['origin']['x'] = -2.5: the domain's first real vertex (-2.5) is not on the "
     f"level-0 grid"),
    (lambda dom: [dom, _set(("coordsets", "coords", "spacing", "dx"), 0.5)(_good())], tessera.DataError,
     "mesh[1]['coordsets']['coords']['spacing']['dx'] = 0.5"),
    (lambda dom: [], tessera.DataError, "no rank published a domain"),
]


@pytest.mark.parametrize("change, kind, message", MALFORMED, ids=[m[2][:40] for m in MALFORMED])
def test_a_malformed_hierarchy_raises_naming_its_path(tmp_path, change, kind, message):
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        with pytest.raises(kind, match=re.escape(message)):
            viz.execute_blueprint(0, 0.0, change(_good()))
        viz.execute_blueprint(2, 0.0, _good())  # the adapter goes on
        assert viz.last_status == 0, viz.last_error


def run_mpi(ranks, tmp_path, case):
    out = tmp_path / f"bp{ranks}{case}.npy"
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1",
               PYTHONPATH=os.pathsep.join([HERE, os.environ.get("PYTHONPATH", "")]))
    subprocess.run(["mpirun", "-n", str(ranks), sys.executable, os.path.join(HERE, "mpi_blueprint_run.py"),
                    str(out), str(tmp_path / f"out{ranks}"), case], check=True, env=env, timeout=120)
    return np.load(out)


def test_mpi4py_two_ranks_equal_one_process(tmp_path):
    """Domains dealt over 2 ranks (uniform cells with ghosts, rectilinear pieces, shared-face
    vertices, vertex and element fields together): the images of one process's execute calls,
    bit for bit."""
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    data = field().T.astype(np.float64)
    cells = dict(domains=[{"fields": {"temperature": data}}], global_dims=data.shape, association="cell", **GRID)
    got = images(tmp_path, cell=("execute", (), cells),
                 rect=("execute", (), dict(cells, coords=axes(*data.shape))),
                 vertex=("execute", ({"temperature": data},), GRID))
    two = run_mpi(2, tmp_path, "images")
    for n, label in enumerate(("cell", "rect", "vertex", "vertex")):
        assert same_bits(got[label], two[n]), label


def test_mpi4py_a_hierarchy_one_rank_cannot_read_fails_on_every_rank_without_a_hang(tmp_path):
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    run_mpi(2, tmp_path, "refused")  # the script asserts; timeout = hang
