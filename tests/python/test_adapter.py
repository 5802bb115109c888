"""tessera.Adapter: the in situ adapter from Python (serial, and mpi4py at -n 2)."""
import os
import re
import shutil
import subprocess
import sys
import warnings

import numpy as np
import pytest

import tessera
from conftest import HERE, field, same_bits

CONFIG = {
    "tessera": {"threads": 2, "on_error": "warn"},
    "renders": [{
        "name": "main",
        "field": "temperature",
        "trigger": {"every": 2},
        "image": {"width": 32, "height": 24, "spp": 4},
        "camera": {"position": {"orbit": {"azimuth": 30, "elevation": 20, "distance": "fit"}},
                   "look_at": "center", "up": [0, 0, 1], "fov": 30},
        "transfer_function": {"range": "auto", "density_scale": 2.0, "opacity": [[0, 0], [1, 1]],
                              "diffuse": "viridis"},
        "integrator": {"seed": 7, "tile": 8},
        "output": {"file": "{name}_{step:03d}", "formats": ["exr"]},
    }],
}
GRID = {"spacing": (1.0, 1.5, 2.0), "origin": (-3, 0, 1)}
# Five uneven boxes ((offset), (size)) tiling the conftest field's (20, 16, 12) elements
DOMAIN_CUTS = [((0, 0, 0), (7, 16, 12)), ((7, 0, 0), (6, 9, 12)), ((7, 9, 0), (6, 7, 12)),
               ((13, 0, 0), (7, 16, 5)), ((13, 0, 5), (7, 16, 7))]


def stretched_y(ny):
    """The ny + 1 cell boundaries of a stretched y axis over [0, 24]."""
    return 24.0 * np.linspace(0.0, 1.0, ny + 1) ** 1.5


def with_ghosts(xyz, g=1, fill=np.nan):
    out = np.full(tuple(n + 2 * g for n in xyz.shape), fill, dtype=xyz.dtype)
    out[g:-g, g:-g, g:-g] = xyz
    return out


def test_execute_returns_the_image_it_writes(tmp_path):
    data = field().T
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        assert viz.execute(1, 0.5, {"temperature": data}, **GRID) == {}  # every: 2
        images = viz.execute(2, 1.0, {"temperature": data}, **GRID)
        assert viz.last_status == 0 and viz.last_error == ""
        result = viz.results[0]
    assert list(images) == ["main"] and images["main"].shape == (24, 32, 4)
    assert result["files"] == [os.path.join(str(tmp_path), "main_002.exr")]
    assert same_bits(images["main"], tessera._tessera._read_exr(result["files"][0]))
    assert (tmp_path / "tessera_effective_config.yaml").exists()


def step0(tmp_path, array, **kw):
    """The image of one adapter's execute at step 0."""
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        return viz.execute(0, 0.0, {"temperature": array}, **GRID, **kw)["main"]


def test_adapter_image_equals_tessera_render(tmp_path):
    data = field().T
    assert same_bits(step0(tmp_path, data), tessera.render(data, CONFIG, **GRID))


def test_ghost_layers_are_skipped(tmp_path):
    data = field(dtype=np.float64).T
    plain = step0(tmp_path, data)
    assert same_bits(plain, step0(tmp_path, with_ghosts(data, 2, 1e30), ghosts=2))
    lo_only = np.full((data.shape[0] + 1, data.shape[1] + 3, data.shape[2]), np.nan)
    lo_only[1:, 3:, :] = data
    assert same_bits(plain, step0(tmp_path, lo_only, ghosts=(1, 3, 0), ghosts_hi=0))


def test_config_errors_name_the_key(tmp_path):
    bad = {"renders": [dict(CONFIG["renders"][0], trigger={"every": 0})]}
    with pytest.raises(tessera.ConfigError) as e:
        tessera.Adapter(bad, output_dir=tmp_path)
    assert e.value.key_path == "renders[0].trigger.every"
    assert str(e.value).startswith("config dict: renders[0].trigger.every: ")
    path = tmp_path / "viz.yaml"
    path.write_text("renders:\n  - name: a\n    colour: red\n")
    with pytest.raises(tessera.ConfigError, match=rf"^{path}:3:5: renders\[0\]\.colour"):
        tessera.Adapter(str(path), output_dir=tmp_path)


def test_failures_follow_on_error(tmp_path):
    data = field().T
    inside = dict(CONFIG["renders"][0], camera={"position": [0, 10, 10], "look_at": [5, 5, 5]})
    warn_cfg = {"tessera": {"on_error": "warn"}, "renders": [inside]}
    with tessera.Adapter(warn_cfg, output_dir=tmp_path, quiet=True) as viz:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            images = viz.execute(0, 0.0, {"wrong_name": data}, **GRID)
        assert images == {} and viz.last_status == 2  # TESSERA_ERROR_DATA
        assert "temperature" in viz.last_error
        assert any(issubclass(w.category, tessera.TesseraWarning) for w in caught)
    abort_cfg = {"tessera": {"on_error": "abort"}, "renders": [inside]}
    with tessera.Adapter(abort_cfg, output_dir=tmp_path, quiet=True) as viz:
        with pytest.raises(tessera.DataError, match="temperature"):
            viz.execute(0, 0.0, {"wrong_name": data}, **GRID)


def test_closed_adapter_and_bad_fields(tmp_path):
    viz = tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True)
    with pytest.raises(TypeError, match="dtype int64"):
        viz.execute(0, 0.0, {"temperature": np.zeros((4, 4, 4), np.int64)})
    viz.close()
    viz.close()  # idempotent
    with pytest.raises(tessera.TesseraError, match="closed"):
        viz.execute(0, 0.0, {"temperature": field().T})


def run_mpi(ranks, tmp_path, *extra):
    out = tmp_path / f"np{ranks}{''.join(extra)}.npy"
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1",
               PYTHONPATH=os.pathsep.join([HERE, os.environ.get("PYTHONPATH", "")]))
    subprocess.run(["mpirun", "-n", str(ranks), sys.executable, os.path.join(HERE, "mpi_adapter_run.py"),
                    str(out), str(tmp_path / f"out{ranks}"), *extra], check=True, env=env, timeout=120)
    return np.load(out)


def test_mpi4py_two_ranks_bit_identical_to_one(tmp_path):
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    one, two = run_mpi(1, tmp_path), run_mpi(2, tmp_path)
    assert one[..., 3].max() > 0.1
    assert same_bits(one, two)


def test_mpi4py_an_array_one_rank_cannot_describe_fails_everywhere_without_a_hang(tmp_path):
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    run_mpi(2, tmp_path, "bad-array-on-last-rank")  # the script asserts; timeout = hang


def test_mpi4py_a_constructor_one_rank_refuses_fails_on_every_rank_without_a_hang(tmp_path):
    """A config that fails to load, or an argument refused, on the last rank only: every rank
    raises from the constructor (mpi_adapter_run.py "refused-open" asserts; timeout = hang)."""
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    run_mpi(2, tmp_path, "refused-open")
    run_mpi(1, tmp_path, "refused-open")


def test_mpi4py_a_communicator_after_mpi_finalize_raises_instead_of_aborting(tmp_path):
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    run_mpi(2, tmp_path, "finalized")


def test_mpi4py_cell_domains_on_a_stretched_axis_two_ranks_bit_identical_to_one(tmp_path):
    """Cell data on a stretched y axis, cut into 5 uneven domains dealt over the ranks of an
    mpi4py communicator (mpi_adapter_run.py "domains"): 1 and 2 ranks, replicated and
    distributed, give the image of one process passing the whole field as one domain."""
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    data = field().T.astype(np.float64)
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        plain = viz.execute(0, 0.0, domains=[{"fields": {"temperature": data}}], global_dims=data.shape,
                            association="cell", coords=(None, stretched_y(data.shape[1]), None), **GRID)["main"]
        assert viz.last_status == 0, viz.last_error
    assert plain[..., 3].max() > 0.1
    assert not same_bits(plain, step0(tmp_path, data))  # not the uniform vertex mesh's image
    one, two = run_mpi(1, tmp_path, "domains"), run_mpi(2, tmp_path, "domains")
    for image in (*one, *two):  # replicated, then distributed
        assert same_bits(plain, image)


def test_domains_cut_uneven_render_bit_identically(tmp_path):
    """The same field as 1 or 5 uneven domains (with NaN ghosts, mixed layouts) gives the
    image of execute(fields), and a zero-copy view of each domain is enough."""
    data = field().T  # (20, 16, 12): u[i, j, k]
    plain = step0(tmp_path, data)
    nx, ny, nz = data.shape
    cuts = [((0, 0, 0), (7, ny, nz)), ((7, 0, 0), (6, 9, nz)), ((7, 9, 0), (6, ny - 9, nz)),
            ((13, 0, 0), (nx - 13, ny, 5)), ((13, 0, 5), (nx - 13, ny, nz - 5))]
    domains = []
    for n, ((i, j, k), (a, b, c)) in enumerate(cuts):
        block = data[i:i + a, j:j + b, k:k + c]
        if n % 2:
            block = np.asfortranarray(block)
        domains.append({"fields": {"temperature": with_ghosts(block, 1)}, "offset": (i, j, k), "ghosts": 1})
    mesh = dict(global_dims=data.shape, **GRID)
    for ds in ([{"fields": {"temperature": data}}], domains, domains[::-1]):
        with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
            images = viz.execute(0, 0.0, domains=ds, **mesh)
            assert viz.last_status == 0, viz.last_error
        assert same_bits(plain, images["main"])


def test_domains_bad_input_names_the_domain(tmp_path):
    data = field().T
    half = data[:10]
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        with pytest.warns(tessera.TesseraWarning, match="cover"):
            viz.execute(0, 0.0, domains=[{"fields": {"temperature": half}}], global_dims=data.shape, **GRID)
        assert viz.last_status == 2  # TESSERA_ERROR_DATA
        with pytest.warns(tessera.TesseraWarning, match="domain 1.*overlap|overlap.*domain 1"):
            viz.execute(0, 0.0, domains=[{"fields": {"temperature": data}}, {"fields": {"temperature": half}}],
                        global_dims=data.shape, **GRID)
        with pytest.raises(ValueError, match="unknown keys"):
            viz.execute(0, 0.0, domains=[{"fields": {"temperature": data}, "offest": 0}], global_dims=data.shape)
        with pytest.raises(TypeError, match="global_dims"):
            viz.execute(0, 0.0, domains=[])
        with pytest.raises(ValueError, match="coords\\[1\\]"):
            viz.execute(0, 0.0, domains=[], global_dims=data.shape, coords=(None, np.zeros(3), None))
        with pytest.raises(TypeError, match="not both"):
            viz.execute(0, 0.0, {"temperature": data}, domains=[], global_dims=data.shape)


class Watched(dict):
    """A dict that counts how often the adapter looks inside it."""
    looks = 0

    def get(self, *args):
        Watched.looks += 1
        return super().get(*args)

    def items(self):
        Watched.looks += 1
        return super().items()

    def __iter__(self):
        Watched.looks += 1
        return super().__iter__()


def test_a_call_where_nothing_fires_never_walks_the_domains(tmp_path):
    """Cost proportional to what fires: at a step no trigger fires, execute looks at none of
    the domains or fields (a million domains cost nothing then; docs/python.md), and at a step
    one fires it reads them all."""
    data = field().T
    cuts = [((i, 0, 0), (1, 16, 12)) for i in range(20)]
    domains = [Watched(fields=Watched(temperature=data[i:i + a]), offset=(i, j, k)) for (i, j, k), (a, _, _) in cuts]
    fields = Watched(temperature=data)
    Watched.looks = 0
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:  # trigger: every 2
        for step in (1, 3, 5):
            assert viz.execute(step, 0.0, domains=domains, global_dims=data.shape, **GRID) == {}
            assert viz.execute(step, 0.0, fields, **GRID) == {}
            assert viz.last_status == 0
        assert Watched.looks == 0
        assert "main" in viz.execute(4, 0.0, domains=domains, global_dims=data.shape, **GRID)
        assert viz.last_status == 0, viz.last_error
        assert Watched.looks >= 2 * len(domains)
        looks = Watched.looks
        assert "main" in viz.execute(6, 0.0, fields, **GRID)
        assert Watched.looks > looks


def test_domains_may_give_fields_their_own_association(tmp_path):
    """A domain's "associations": a cell field beside the vertex field on a vertex mesh (one
    element fewer per axis) leaves the vertex field's image as it is; bad entries are refused
    naming them."""
    data = field().T
    cells = np.ascontiguousarray(data[1:, 1:, 1:])
    dom = {"fields": {"temperature": data, "energy": cells}, "associations": {"energy": "cell"}}
    with tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True) as viz:
        plain = viz.execute(0, 0.0, {"temperature": data}, **GRID)["main"]
        mixed = viz.execute(0, 0.0, domains=[dom], global_dims=data.shape, **GRID)["main"]
        assert viz.last_status == 0, viz.last_error
        for bad, message in (({"energy": "element"}, "['energy']: 'vertex' or 'cell' is needed"),
                             ({"pressure": "cell"}, "'pressure' is not one of the domain's fields")):
            with pytest.raises(ValueError, match=re.escape(f"domains[0]['associations']{message}"
                                                           if message.startswith("[") else message)):
                viz.execute(0, 0.0, domains=[dict(dom, associations=bad)], global_dims=data.shape, **GRID)
    assert same_bits(plain, mixed)
