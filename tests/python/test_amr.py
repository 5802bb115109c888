"""tessera.Adapter with refinement levels (AMR): a two-level hierarchy renders the same bits
for any cut into patches, any rank count (mpi4py, -n 1 and -n 2) and both distribution modes;
a linear field at two levels gives the single level's image within noise (z-test); a large
patch is never read past its elements; bad level arguments get clear errors."""
import copy
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import tessera
from amr_hierarchy import AMR_CONFIG, DIMS0, MESH, level, patches, whole
from conftest import HERE, same_bits
from test_adapter import GRID


def render(tmp_path, domains, config=AMR_CONFIG, **mesh):
    with tessera.Adapter(config, output_dir=tmp_path, quiet=True) as viz:
        images = viz.execute(0, 0.0, domains=domains, **(mesh or MESH))
        assert viz.last_status == 0, viz.last_error
    return images["main"]


def run_mpi(ranks, tmp_path):
    out = tmp_path / f"amr{ranks}.npy"
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1",
               PYTHONPATH=os.pathsep.join([HERE, os.environ.get("PYTHONPATH", "")]))
    subprocess.run(["mpirun", "-n", str(ranks), sys.executable, os.path.join(HERE, "mpi_amr_run.py"), str(out),
                    str(tmp_path / f"out{ranks}")], check=True, env=env, timeout=120)
    return np.load(out)


def test_two_levels_any_cut_and_rank_count_bit_identical(tmp_path):
    one = render(tmp_path, whole())
    assert one[..., 3].max() > 0.1
    # The fine level is read: shifting its values changes the image (level 0 alone may give the
    # same bits: this view barely sees the fine detail, and the walk's random numbers need not
    # depend on the fine level's majorants)
    assert not same_bits(one, render(tmp_path, whole(fine_offset=0.5)))
    assert same_bits(one, render(tmp_path, patches()))
    assert same_bits(one, render(tmp_path, patches()[::-1]))
    pytest.importorskip("mpi4py")
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    for image in (*run_mpi(1, tmp_path), *run_mpi(2, tmp_path)):  # replicated, then distributed
        assert same_bits(one, image)


def test_linear_field_at_two_levels_matches_one_level(tmp_path):
    """A field linear in x, y, z has the same value at every level, so the two-level image and
    the single-level one have the same expectation. Level 1 covers most of the volume (level-0
    vertices [1, 19] x [1, 15] x [1, 11]); the two renders use different seeds (independent
    noise), and over the image's pixels the mean difference of opacity (alpha; the config has
    no lights) is within 4 standard errors of 0 (z-test, 99.99% two-sided; seeds 7 and 8,
    64 spp, density scale 0.1 so that alpha is far from 0 and 1). The test's power: the same
    fine level offset by +0.3 (9% of the transfer function's range) gives |z| > 4."""
    def linear(u, v, w):
        return 0.15 * u - 0.1 * v + 0.2 * w - 0.5

    def config(seed):
        c = copy.deepcopy(AMR_CONFIG)
        c["renders"][0]["image"] = {"width": 48, "height": 36, "spp": 64}
        c["renders"][0]["integrator"] = {"seed": seed, "tile": 8}
        c["renders"][0]["transfer_function"]["density_scale"] = 0.1
        return c

    def z(a, b):
        d = (a[..., 3].astype(np.float64) - b[..., 3].astype(np.float64)).ravel()
        return d.mean() / (d.std(ddof=1) / np.sqrt(d.size))

    box = dict(lo=(2, 2, 2), n=(37, 29, 21))
    single = render(tmp_path, whole(linear)[:1], config(8), global_dims=DIMS0, **GRID)
    assert 0.1 < single[..., 3].mean() < 0.9  # neither blank nor opaque
    z_same = z(render(tmp_path, whole(linear, **box), config(7)), single)
    assert abs(z_same) < 4.0, f"z = {z_same:.2f}: the two-level image is biased against the single level"
    z_off = z(render(tmp_path, whole(linear, fine_offset=0.3, **box), config(7)), single)
    assert abs(z_off) > 4.0, f"z = {z_off:.2f}: the test cannot tell a fine level offset by 0.3"


def test_level_arguments_are_checked(tmp_path):
    domains = whole()
    with tessera.Adapter(AMR_CONFIG, output_dir=tmp_path, quiet=True) as viz:
        mesh = dict(global_dims=DIMS0, **GRID)
        with pytest.raises(ValueError, match="refinement: nlevels - 1 = 1 ratio"):
            viz.execute(0, 0.0, domains=domains, nlevels=2, refinement=[2, 2], **mesh)
        with pytest.raises(TypeError, match="refinement: 1 ratio"):
            viz.execute(0, 0.0, domains=domains, nlevels=2, **mesh)
        with pytest.raises(TypeError, match="refinement\\[0\\]"):
            viz.execute(0, 0.0, domains=domains, nlevels=2, refinement=[2.0], **mesh)
        with pytest.raises(TypeError, match="refinement: a list"):
            viz.execute(0, 0.0, domains=domains, nlevels=2, refinement=2, **mesh)
        with pytest.raises(ValueError, match="nlevels: 1 .. 8"):
            viz.execute(0, 0.0, domains=domains, nlevels=9, refinement=[2] * 8, **mesh)
        with pytest.raises(TypeError, match="nlevels"):
            viz.execute(0, 0.0, domains=domains, nlevels="2", refinement=[2], **mesh)
        with pytest.raises(TypeError, match="need domains"):
            viz.execute(0, 0.0, {"temperature": domains[0]["fields"]["temperature"]}, nlevels=2, refinement=[2])
        # A ratio other than 2 or 4, a level >= nlevels: the adapter's data errors
        with pytest.warns(tessera.TesseraWarning, match="refinement|ratio"):
            viz.execute(0, 0.0, domains=domains, nlevels=2, refinement=[3], **mesh)
        assert viz.last_status == 2  # TESSERA_ERROR_DATA
        with pytest.warns(tessera.TesseraWarning, match="level"):
            viz.execute(0, 0.0, domains=domains, nlevels=1, **mesh)
        assert viz.last_status == 2


def test_a_large_patch_is_read_only_inside_its_elements(tmp_path):
    """A level-1 patch of 130^3 vertices (129^3 stencil cells: more than the level table holds
    one per entry, and an odd count, so the table's last cells are partial) passed as a view
    into an array padded with 1e30 renders the same bits as its compact copy: no lookup reads
    past the patch (a read there would take the padding in one and a neighbouring row in the
    other)."""
    dims0, lo, n = (70, 70, 70), (4, 4, 4), (130, 130, 130)

    def field(u, v, w):
        return np.sin(u / 9.0) * np.cos(v / 11.0) + w / 70.0

    padded = np.full(tuple(m + 2 for m in n), 1e30, dtype=np.float32)
    padded[1:-1, 1:-1, 1:-1] = level(1, lo, n, fn=field).astype(np.float32)
    view = padded[1:-1, 1:-1, 1:-1]
    coarse = level(0, n=dims0, fn=field).astype(np.float32)
    mesh = dict(global_dims=dims0, nlevels=2, refinement=[2], spacing=1.0, origin=0.0)
    config = copy.deepcopy(AMR_CONFIG)
    config["renders"][0]["image"] = {"width": 64, "height": 48, "spp": 16}
    config["renders"][0]["transfer_function"]["density_scale"] = 0.05
    images = [render(tmp_path, [{"fields": {"temperature": coarse}},
                                {"fields": {"temperature": fine}, "offset": lo, "level": 1}], config, **mesh)
              for fine in (view, np.ascontiguousarray(view))]
    assert images[0][..., 3].max() > 0.1
    assert same_bits(images[0], images[1])
