"""Adapter.execute_mesh_domains and execute_blueprint's explicit coordinate sets: curvilinear
and unstructured meshes read in place (docs/python.md, "Curvilinear and unstructured meshes").

The example (mesh_example.py) renders pictures; the shell published as a curvilinear grid, as
unstructured hexes (int32 or int64, flat or (ncells, 8)), with its coordinates as one (n, 3)
array, three strided rows or three 3-D arrays, and as Blueprint structured and unstructured
topologies, gives the same image bit for bit; malformed domains are refused naming the domain,
key and fault (by the package) or the domain and element (by the adapter).
"""
import os
import sys
import warnings

import numpy as np
import pytest

import tessera

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mesh_example  # noqa: E402

SMALL = {"tessera": {"threads": 2, "on_error": "abort"},
         "renders": [{"field": "f", "image": {"width": 40, "height": 30, "spp": 4}}]}
NI, NJ, NK = mesh_example.NI, mesh_example.NJ, mesh_example.NK


@pytest.fixture(scope="module")
def shell():
    return mesh_example.shell()


def render(tmp_path, domains, name="r"):
    with tessera.Adapter(SMALL, output_dir=str(tmp_path / name), quiet=True) as viz:
        images = viz.execute_mesh_domains(0, 0.0, domains)
        assert viz.last_status == 0, viz.last_error
    return images["f"]


def test_example_renders_pictures(tmp_path):
    images = mesh_example.main(str(tmp_path))
    for name, image in images.items():
        lum = image[..., :3].mean(axis=-1)
        assert image.shape == (512, 512, 4) and np.all(np.isfinite(image)), name
        assert lum.std() > 0.01 and np.mean(np.abs(lum - np.median(lum)) > 0.05) > 0.01, f"{name} is flat"
        assert os.path.getsize(tmp_path / name / "f_000000.png") > 0


def test_curvilinear_equals_hexes_bit_for_bit(tmp_path, shell):
    xyz, f, hexes = shell
    grid = render(tmp_path, [{"coords": xyz, "dims": (NI, NJ, NK), "fields": {"f": f}}], "grid")
    assert grid[..., :3].std() > 0
    rows = xyz.T.copy()  # three contiguous rows
    x3 = [np.asfortranarray(xyz[:, a].reshape(NK, NJ, NI).T) for a in range(3)]  # [i, j, k], i fastest
    f3 = f.reshape(NK, NJ, NI).T  # the .T of a C-ordered (nk, nj, ni) array: read in place
    same = [
        [{"coords": xyz, "shape": "hex", "connectivity": hexes, "fields": {"f": f}}],
        [{"coords": xyz, "shape": "hex", "connectivity": hexes.astype(np.int32).ravel(), "fields": {"f": f}}],
        [tessera.MeshDomain(coords=[xyz[:, 0], xyz[:, 1], xyz[:, 2]], dims=(NI, NJ, NK), fields={"f": f})],
        [{"coords": list(rows), "dims": (NI, NJ, NK), "fields": {"f": f3}}],
        [{"coords": x3, "dims": (NI, NJ, NK), "fields": {"f": f[::1]}}],
        # Two domains: the hexes cut in two, each list with all the vertices
        [{"coords": xyz, "shape": "hex", "connectivity": hexes[:700], "fields": {"f": f}},
         {"coords": xyz, "shape": "hex", "connectivity": hexes[700:], "fields": {"f": f}}],
    ]
    for n, domains in enumerate(same):
        assert np.array_equal(render(tmp_path, domains, f"same{n}"), grid), f"variant {n}"


def test_results_say_whether_the_lookup_structure_was_reused(tmp_path, shell):
    xyz, f, hexes = shell
    domains = [{"coords": xyz, "shape": "hex", "connectivity": hexes, "fields": {"f": f}}]
    with tessera.Adapter(SMALL, output_dir=str(tmp_path / "reuse"), quiet=True) as viz:
        seen = []
        for step, geometry in enumerate([xyz, xyz, xyz + 1e-3]):
            domains[0]["coords"] = geometry
            viz.execute_mesh_domains(step, 0.1 * step, domains)
            assert viz.last_status == 0, viz.last_error
            (r,) = viz.results
            assert r["mesh_values_only"] is False and r["mesh_exchange_bytes"] == 0  # one rank
            assert r["mesh_summary_shared"] is False
            seen.append(r["mesh_layout_reused"])
    assert seen == [False, True, False]  # the same geometry found by its hash; a moved one rebuilt


def test_cell_data_and_ghosts(tmp_path, shell):
    xyz, _, hexes = shell
    cells = np.linspace(0.0, 1.0, len(hexes))
    ghost = np.zeros(len(hexes), np.uint8)
    plain = render(tmp_path, [{"coords": xyz, "shape": "hex", "connectivity": hexes, "association": "cell",
                               "fields": {"f": cells}}], "cells")
    curvilinear = render(tmp_path, [{"coords": xyz, "dims": (NI, NJ, NK), "associations": {"f": "cell"},
                                     "fields": {"f": cells, "g": ghost}, "ghost_field": "g"}], "ghosts")
    assert np.array_equal(plain, curvilinear)


def test_blueprint_structured_and_unstructured(tmp_path, shell):
    xyz, f, hexes = shell
    grid = render(tmp_path, [{"coords": xyz, "dims": (NI, NJ, NK), "fields": {"f": f}}], "grid")

    def mesh(topology):
        m = {"coordsets/c/type": "explicit", "coordsets/c/values/x": xyz[:, 0], "coordsets/c/values/y": xyz[:, 1],
             "coordsets/c/values/z": xyz[:, 2], "topologies/t/coordset": "c",
             "fields/f/association": "vertex", "fields/f/topology": "t", "fields/f/values": f}
        m.update(topology)
        return m

    structured = mesh({"topologies/t/type": "structured", "topologies/t/elements/dims/i": NI - 1,
                       "topologies/t/elements/dims/j": NJ - 1, "topologies/t/elements/dims/k": NK - 1})
    unstructured = mesh({"topologies/t/type": "unstructured", "topologies/t/elements/shape": "hex",
                         "topologies/t/elements/connectivity": hexes.ravel()})
    unstructured["fields/vtkGhostType/association"] = "element"
    unstructured["fields/vtkGhostType/topology"] = "t"
    unstructured["fields/vtkGhostType/values"] = np.zeros(len(hexes), np.int32)  # made a uint8 mask
    for n, m in enumerate((structured, unstructured, [structured])):
        with tessera.Adapter(SMALL, output_dir=str(tmp_path / f"bp{n}"), quiet=True) as viz:
            assert np.array_equal(viz.execute_blueprint(0, 0.0, m)["f"], grid), n


def test_nothing_looked_at_where_nothing_fires(tmp_path):
    config = dict(SMALL, renders=[dict(SMALL["renders"][0], trigger={"every": 2})])
    with tessera.Adapter(config, output_dir=str(tmp_path), quiet=True) as viz:
        assert viz.execute_mesh_domains(1, 0.1, [7, "not a domain"]) == {}


def _bad(shell, **change):
    xyz, f, hexes = shell
    dom = {"coords": xyz, "shape": "hex", "connectivity": hexes, "fields": {"f": f}}
    dom.update(change)
    return [{k: v for k, v in dom.items() if v is not None}]


REFUSED = [  # (change, exception, what the message says)
    (dict(fields={"f": np.zeros(10)}), ValueError, "domains[0]['fields']['f']: 2673 values are needed, one per vertex"),
    (dict(fields={"f": np.zeros(2673, np.int64)}), TypeError,
     "domains[0]['fields']['f']: dtype int64 is not supported"),
    (dict(connectivity=np.zeros((10, 8))), TypeError, "domains[0]['connectivity']: dtype float64 is not supported"),
    (dict(connectivity=np.zeros(12, np.int64)), ValueError, "8 vertex indices per hex are needed"),
    (dict(connectivity=np.zeros((16, 8), np.int64)[::2]), ValueError, "domains[0]['connectivity']: a C-contiguous"),
    (dict(shape="wedge"), ValueError, "wedge elements are not yet supported"),
    (dict(shape=None, connectivity=None), ValueError, "dims (a curvilinear domain) or shape and connectivity"),
    (dict(dims=(9, 33, 8), shape=None, connectivity=None), ValueError, "dims = (9, 33, 8) needs 2376 vertices"),
    (dict(coords=[np.zeros(2673), np.zeros(2673, np.float32), np.zeros(2673)]), ValueError,
     "domains[0]['coords'][1] (y): its dtype (float32) differs from x's (float64)"),
    (dict(coords=[np.zeros(2673), np.zeros(5346)[::2], np.zeros(2673)]), ValueError, "its byte stride (16) differs"),
    (dict(fields={"f": np.zeros(2673), "g": np.zeros(2048, np.float32)}, ghost_field="g"), TypeError,
     "domains[0]['fields']['g']: the ghost field must be uint8"),
    (dict(ghost_field="h"), ValueError, "domains[0]['ghost_field'] = 'h': not one of the domain's fields"),
    (dict(coords=np.zeros((2673, 2))), ValueError, "an (n, 3) array (one row per vertex)"),
]


@pytest.mark.parametrize("change, exception, message", REFUSED)
def test_malformed_refused_by_the_package(tmp_path, shell, change, exception, message):
    with tessera.Adapter(SMALL, output_dir=str(tmp_path), quiet=True) as viz:
        with pytest.raises(exception) as e:
            viz.execute_mesh_domains(0, 0.0, _bad(shell, **change))
        assert message in str(e.value)
        assert viz.execute_mesh_domains(0, 0.0, _bad(shell))["f"] is not None  # the adapter still renders


def test_malformed_refused_by_the_adapter(tmp_path, shell):
    xyz, f, hexes = shell
    out_of_range, inverted, nan = hexes.copy(), hexes.copy(), xyz.copy()
    out_of_range[4, 2] = len(xyz)
    inverted[4] = np.concatenate([hexes[4, 4:], hexes[4, :4]])  # the top face first: inside out
    nan[hexes[4, 0], 1] = np.nan
    cases = [(_bad(shell, connectivity=out_of_range), "element 4: vertex index 2673 (entry 2) is outside [0, 2673)"),
             (_bad(shell, connectivity=inverted), "element 4: hex is inverted"),
             (_bad(shell, coords=nan), "non-finite coordinate")]
    for n, (domains, message) in enumerate(cases):  # on_error: abort: an adapter per fault
        with tessera.Adapter(SMALL, output_dir=str(tmp_path / str(n)), quiet=True) as viz:
            with pytest.raises(tessera.DataError) as e:
                viz.execute_mesh_domains(0, 0.0, domains)
            assert "mesh domain 0" in str(e.value) and message in str(e.value), str(e.value)
    warn = dict(SMALL, tessera={"threads": 2})  # on_error: warn
    with tessera.Adapter(warn, output_dir=str(tmp_path / "warn"), quiet=True) as viz:
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            assert viz.execute_mesh_domains(0, 0.0, cases[1][0]) == {}
        assert viz.last_status == 2 and "hex is inverted" in viz.last_error and w
