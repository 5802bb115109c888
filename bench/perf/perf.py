"""Performance benchmarks of tessera-render: run time against error, the thesis' tiling study,
thread scaling, samples per second, and the targets of docs/BENCHMARKS.md.

    python3 bench/perf/perf.py --build BUILD --results bench/results [--quick] [--only a,b]

Studies (--only): data, error, thesis, scaling, targets, cache (the default run), and cachebig,
rescore (on request). Each writes CSV files into the
results directory; report.py turns them into markdown tables and plot.py into PNG plots.
Benchmarks are not tests: nothing here asserts a time.
"""
import argparse
import glob
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_lib import (DATASETS, MACROCELL, Bench, ensure_volume, log, read_csv,  # noqa: E402
                      render_entry, rmse, run_scene, stat_row, wait_for_idle, warmup_entry,
                      write_csv, write_scene)

CLOSE, FAR = 2.0, 6.0  # camera distances in bounding-sphere radii (close fills the frame)
MACROCELL_SWEEP = (1, 2, 4, 8, 16, 32)  # macrocell edges (voxels) of the majorant study


def settings(quick):
    """What each study renders; --quick keeps the whole run under about five minutes."""
    if quick:
        return {
            "err_size": 64, "err_ref_spp": 256, "err_spp_delta": [4, 16, 64], "err_spp_rm": [4, 16],
            "err_targets": [0.1, 0.05], "err_sets": ["heat", "blobs", "smooth", "ct"],
            "th_size": 128, "th_sets": ["engine"], "th_reps": 1,
            "th_serial": [2, 4, 8, 16, 32, 64, 128, 256], "th_tbb": [8, 16, 32, 64, 128, 256, 512],
            "th_morton": [2, 8],
            "sc_size": 128, "sc_spp": 4, "sc_sets": ["blobs", "smooth", "ct", "engine"], "sc_reps": 1,
            "cull_size": 256, "cull_spp": 4, "mc_size": 64,
            "cache_set": "engine", "cache_size": 32, "cache_spp": 4, "cache_tiles": [2, 8], "idle_wait": 0,
        }
    return {
        "err_size": 128, "err_ref_spp": 1024, "err_spp_delta": [4, 16, 64, 256],
        "err_spp_rm": [4, 16, 64], "err_targets": [0.1, 0.05, 0.025],
        "err_sets": ["heat", "blobs", "smooth", "ct"],
        "th_size": 256, "th_sets": ["engine", "manix", "macoessix"], "th_reps": 2,
        "th_serial": [2, 4, 8, 16, 32, 64, 128, 256], "th_tbb": [8, 16, 32, 64, 128, 256, 512],
        "th_morton": [2, 8, 32],
        "sc_size": 256, "sc_spp": 8,
        "sc_sets": ["blobs", "smooth", "ct", "engine", "manix", "macoessix"], "sc_reps": 2,
        "cull_size": 512, "cull_spp": 16, "mc_size": 128,
        "cache_set": "manix", "cache_size": 64, "cache_spp": 20,
        "cache_tiles": [2, 4, 8, 16, 32], "idle_wait": 30,
    }


def render_cpu(r, prepare_floor):
    """CPU seconds of one render without its prepare step (the smallest prepare wall time seen
    for the volume stands in for prepare's CPU time, which contention does not inflate)."""
    return max(0.0, r["cpu_seconds"] - prepare_floor)


def tag(x):
    """A number as a render-name fragment (names allow letters, digits, _ and -): 0.25 -> 0p25."""
    return f"{x:g}".replace(".", "p")


def clean_images(out_dir):
    shutil.rmtree(out_dir, ignore_errors=True)


# ----------------------------------------------------------------------------------------------
# Run time against error
# ----------------------------------------------------------------------------------------------

def study_error(b, S):
    rows = []
    for name in S["err_sets"]:
        vol = ensure_volume(b, name)
        if vol is None:
            log(f"error: {name} unavailable, skipped")
            continue
        ds = DATASETS[name]
        size = S["err_size"]
        clean_images(b.dir("img", "error", name))
        out = b.dir("img", "error", name)
        # Reference: delta tracking on the grid at high spp, all threads, with its variance
        ref_scene = b.path("scenes", f"error_{name}_ref.yaml")
        write_scene(b, ref_scene, name, vol, [render_entry("reference", ds, width=size, height=size,
                    spp=S["err_ref_spp"], seed=987654321, variance=True)], 0, out)
        log(f"error/{name}: reference {size}x{size}, {S['err_ref_spp']} spp")
        ref = run_scene(b, ref_scene, b.path("stats", f"error_{name}_ref.json"))[0]
        ref_exr = os.path.join(out, "reference.exr")

        # The methods, one thread, each at several sample counts
        entries, meta = [warmup_entry(ds)], {}

        def add(nm, spp, integ, method, param, target=0.0):
            entries.append(render_entry(nm, ds, width=size, height=size, spp=spp,
                                        integrator=integ, target_error=target))
            meta[nm] = {"method": method, "param": param, "spp": spp}

        for step in (2.0, 1.0, 0.5, 0.25):
            for spp in S["err_spp_rm"]:
                add(f"raymarch_{tag(step)}_spp{spp}", spp, {"free_path": "raymarch", "step": step},
                    "raymarch", step)
        for spp in S["err_spp_rm"]:
            add(f"delta_global_spp{spp}", spp, {"majorant": "global"}, "delta_global", "")
        for spp in S["err_spp_delta"]:
            add(f"delta_grid_spp{spp}", spp, {}, "delta_grid", MACROCELL)
        top = S["err_spp_delta"][-1]
        for t in S["err_targets"]:
            add(f"adaptive_{tag(t)}_spp{top}", top, {}, "delta_grid_adaptive", t, target=t)
        # (every render above uses macrocells of MACROCELL voxels unless it says otherwise)
        scene = b.path("scenes", f"error_{name}.yaml")
        write_scene(b, scene, name, vol, entries, 1, out)
        log(f"error/{name}: {len(entries) - 1} renders, 1 thread")
        res = run_scene(b, scene, b.path("stats", f"error_{name}.json"))[1:]
        prep = min(r["prepare_seconds"] for r in res)
        for r in res:
            rows.append(stat_row(r, dataset=name, render=r["name"], **meta[r["name"]],
                                 render_cpu_s=render_cpu(r, prep), ref_spp=S["err_ref_spp"],
                                 size=size))
    score_error(b, rows)


def score_error(b, rows):
    """Adds the errors against each data set's reference (tessera-rmse) and writes the CSV."""
    for name in dict.fromkeys(r["dataset"] for r in rows):
        out = os.path.join(b.results, "img", "error", name)
        mine = [r for r in rows if r["dataset"] == name]
        errs = rmse(b, os.path.join(out, "reference.exr"),
                    [os.path.join(out, r["render"] + ".exr") for r in mine])
        for r in mine:
            e = errs[os.path.join(out, r["render"] + ".exr")]
            corr = max(0.0, e["rmse_lum"] ** 2 - e["ref_var_lum"]) ** 0.5
            r.update({"rmse_lum": e["rmse_lum"], "rmse_lum_corrected": corr,
                      "rel_rmse_lum": corr / e["mean_lum_ref"] if e["mean_lum_ref"] > 0 else 0.0,
                      "relmse_corrected": max(0.0, e["relmse_lum"] - e["ref_relvar_lum"]),
                      "rmse_rgb": e["rmse_rgb"], "ref_noise_lum": e["ref_var_lum"] ** 0.5})
    write_csv(b.path("error_vs_time.csv"), rows)


def study_rescore(b, S):
    """Recomputes the errors of the last error study from its images (after changing
    tessera-rmse), keeping its timings."""
    rows = read_csv(b.path("error_vs_time.csv"))
    for r in rows:
        if "render" not in r:  # CSV files written before the render column existed
            m = r["method"]
            p = (f"raymarch_{tag(r['param'])}" if m == "raymarch" else
                 f"adaptive_{tag(r['param'])}" if m == "delta_grid_adaptive" else m)
            r["render"] = f"{p}_spp{r['spp']}"
    score_error(b, rows)


# ----------------------------------------------------------------------------------------------
# The thesis' tiling study
# ----------------------------------------------------------------------------------------------

def thesis_configs(S, threads):
    """(label, tile, order) per configuration; tiles that cover the whole image are 'full'."""
    size = S["th_size"]
    tiles = S["th_serial"] if threads == 1 else S["th_tbb"]
    cfgs = [("full", size, "row"), ("scanline", 0, "row")]
    cfgs += [(str(t), t, "row") for t in tiles if t < size]
    if threads == 1:
        cfgs += [(f"morton{t}", t, "morton") for t in S["th_morton"]]
    return cfgs


def study_thesis(b, S):
    rows = []
    size = S["th_size"]
    for name in S["th_sets"]:
        vol = ensure_volume(b, name)
        ds = DATASETS[name]
        for threads in (1, 2):
            out = b.dir("img", "thesis", f"{name}_{threads}")
            entries, meta = [warmup_entry(ds)], {}
            # Far views render in a fraction of a second, where one burst of other work on the
            # machine doubles a time: they get two more repeats.
            for rep in range(S["th_reps"] + 2):
                for cam, dist in (("close", CLOSE), ("far", FAR)):
                    if cam == "close" and rep >= S["th_reps"]:
                        continue
                    for label, tile, order in thesis_configs(S, threads):
                        nm = f"{cam}_{label}_r{rep}"
                        entries.append(render_entry(nm, ds, width=size, height=size, spp=20,
                                                    distance=dist, tile=tile, order=order,
                                                    integrator={"culling": False}))
                        meta[nm] = {"camera": cam, "config": label, "tile": tile, "order": order,
                                    "rep": rep}
            scene = b.path("scenes", f"thesis_{name}_t{threads}.yaml")
            write_scene(b, scene, name, vol, entries, threads, out)
            log(f"thesis/{name}: {len(entries) - 1} renders of {size}x{size}x20, {threads} thread(s)")
            idle = wait_for_idle(S["idle_wait"]) if threads > 1 else float("nan")
            res = run_scene(b, scene, b.path("stats", f"thesis_{name}_t{threads}.json"))[1:]
            prep = min(r["prepare_seconds"] for r in res)
            for r in res:
                rows.append(stat_row(r, dataset=name, threads_req=threads, size=size,
                                     render_cpu_s=render_cpu(r, prep), idle_cores_before=idle,
                                     **meta[r["name"]]))
            clean_images(out)
    write_csv(b.path("thesis_tiles.csv"), rows)


# ----------------------------------------------------------------------------------------------
# Thread scaling and samples per second
# ----------------------------------------------------------------------------------------------

def study_scaling(b, S):
    rows = []
    size, spp = S["sc_size"], S["sc_spp"]
    for name in S["sc_sets"]:
        vol = ensure_volume(b, name)
        if vol is None:
            log(f"scaling: {name} unavailable, skipped")
            continue
        ds = DATASETS[name]
        for threads in (1, 2):
            out = b.dir("img", "scaling", f"{name}_{threads}")
            entries = [warmup_entry(ds)]
            for rep in range(S["sc_reps"]):
                entries.append(render_entry(f"close_r{rep}", ds, width=size, height=size, spp=spp))
            scene = b.path("scenes", f"scaling_{name}_t{threads}.yaml")
            write_scene(b, scene, name, vol, entries, threads, out)
            log(f"scaling/{name}: {size}x{size}x{spp}, {threads} thread(s)")
            idle = wait_for_idle(S["idle_wait"]) if threads > 1 else float("nan")
            res = run_scene(b, scene, b.path("stats", f"scaling_{name}_t{threads}.json"))[1:]
            prep = min(r["prepare_seconds"] for r in res)
            for rep, r in enumerate(res):
                rows.append(stat_row(r, dataset=name, threads_req=threads, rep=rep, size=size,
                                     spp=spp, voxels=ds["dims"][0] * ds["dims"][1] * ds["dims"][2],
                                     render_cpu_s=render_cpu(r, prep), idle_cores_before=idle))
            clean_images(out)
    write_csv(b.path("scaling.csv"), rows)


# ----------------------------------------------------------------------------------------------
# Targets: majorant grid against global majorant, culling
# ----------------------------------------------------------------------------------------------

def study_targets(b, S):
    # Lookups per real collision against the macrocell size, and the global majorant
    rows = []
    size = S["mc_size"]
    for name in ("heat", "blobs", "smooth", "ct"):
        vol = ensure_volume(b, name)
        if vol is None:
            continue
        ds = DATASETS[name]
        out = b.dir("img", "majorant", name)
        entries = [warmup_entry(ds)]
        for mc in MACROCELL_SWEEP:
            entries.append(render_entry(f"grid{mc}", ds, width=size, height=size, spp=8,
                                        integrator={"macrocell": mc}))
        entries.append(render_entry("global", ds, width=size, height=size, spp=8,
                                    integrator={"majorant": "global"}))
        scene = b.path("scenes", f"majorant_{name}.yaml")
        write_scene(b, scene, name, vol, entries, 1, out)
        log(f"targets/majorant/{name}")
        res = run_scene(b, scene, b.path("stats", f"majorant_{name}.json"))[1:]
        for r in res:
            # prepare differs with the macrocell size here: each render's own is subtracted
            rows.append(stat_row(r, dataset=name, config=r["name"], size=size,
                                 render_cpu_s=render_cpu(r, r["prepare_seconds"])))
        clean_images(out)
    write_csv(b.path("majorant.csv"), rows)

    # Culling: a small volume far away in a big image, culling on and off
    rows = []
    ds = DATASETS["blobs"]
    vol = ensure_volume(b, "blobs")
    size = S["cull_size"]
    out = b.dir("img", "culling")
    entries = [warmup_entry(ds)]
    for rep in range(2):
        for cull in (True, False):
            entries.append(render_entry(f"culling_{'on' if cull else 'off'}_r{rep}", ds, width=size,
                                        height=size, spp=S["cull_spp"], distance=12.0,
                                        integrator={"culling": cull}))
    scene = b.path("scenes", "culling.yaml")
    write_scene(b, scene, "blobs", vol, entries, 1, out)
    log(f"targets/culling: {size}x{size}x{S['cull_spp']}, volume at 12 radii")
    res = run_scene(b, scene, b.path("stats", "culling.json"))[1:]
    prep = min(r["prepare_seconds"] for r in res)
    for r in res:
        rows.append(stat_row(r, config=r["name"].rsplit("_r", 1)[0], size=size, spp=S["cull_spp"],
                             render_cpu_s=render_cpu(r, prep)))
    clean_images(out)
    write_csv(b.path("culling.csv"), rows)


# ----------------------------------------------------------------------------------------------
# Cache behaviour (cachegrind)
# ----------------------------------------------------------------------------------------------

# The host's L1d (48 KiB, 12-way) and L2 (2 MiB, 16-way) as D1 and LL: the 105 MiB L3 is shared
# with other tenants and not a power of two, which cachegrind cannot simulate.
CG_CACHES = ["--D1=49152,12,64", "--LL=2097152,16,64", "--I1=32768,8,64"]


def read_cg_summary(out_file):
    """{event: count} from the summary line of a cachegrind or callgrind output file."""
    events, summary = None, None
    with open(out_file) as f:
        for line in f:
            if line.startswith("events:"):
                events = line.split()[1:]
            elif line.startswith("summary:"):
                summary = [int(x) for x in line.split()[1:]]
    return dict(zip(events, summary))


def cachegrind(b, scene, tag):
    out_file = b.path("cachegrind", f"{tag}.out")
    subprocess.run(["valgrind", "--tool=cachegrind", "--cache-sim=yes", *CG_CACHES,
                    f"--cachegrind-out-file={out_file}", b.render_exe, scene, "--quiet"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return read_cg_summary(out_file)


def cache_row(name, size, spp, label, tile, c):
    refs = c["Dr"] + c["Dw"]
    return {"dataset": name, "size": size, "spp": spp, "config": label, "tile": tile,
            "Ir": c["Ir"], "Drefs": refs, "D1_misses": c["D1mr"] + c["D1mw"],
            "LL_misses": c["DLmr"] + c["DLmw"],
            "D1_miss_rate": (c["D1mr"] + c["D1mw"]) / refs,
            "LL_miss_rate": (c["DLmr"] + c["DLmw"]) / refs,
            "LL_misses_per_kIr": 1000.0 * (c["DLmr"] + c["DLmw"]) / c["Ir"],
            # cachegrind's old rough cycle model: 10 per L1 miss, 100 per LL miss
            "est_cycles": c["Ir"] + 10 * (c["I1mr"] + c["D1mr"] + c["D1mw"]) +
            100 * (c["ILmr"] + c["DLmr"] + c["DLmw"])}


def study_cache(b, S):
    if shutil.which("valgrind") is None:
        log("cache: valgrind not found, skipped")
        return
    name, size, spp = S["cache_set"], S["cache_size"], S["cache_spp"]
    ds = DATASETS[name]
    vol = ensure_volume(b, name)
    out = b.dir("img", "cache")
    rows = []
    # The baseline (load, prepare, one 1x1 sample) is subtracted from every configuration
    configs = [("baseline", 1, 1, 8)] + [(f"tile{t}", size, spp, t) for t in S["cache_tiles"]]
    configs += [(f"full{size}", size, spp, size), ("scanline", size, spp, 0)]
    counts = {}
    for label, sz, s, tile in configs:
        scene = b.path("scenes", f"cache_{label}.yaml")
        write_scene(b, scene, name, vol, [render_entry(label, ds, width=sz, height=sz, spp=s,
                                                       distance=CLOSE, tile=tile,
                                                       integrator={"culling": False})], 1, out)
        log(f"cache: cachegrind {name} {sz}x{sz}x{s} {label}")
        counts[label] = cachegrind(b, scene, label)
    base = counts["baseline"]
    for label, _, _, tile in configs[1:]:
        rows.append(cache_row(name, size, spp, label, tile,
                              {k: counts[label][k] - base[k] for k in base}))
    clean_images(out)
    write_csv(b.path("cachegrind.csv"), rows)


def study_cachebig(b, S):
    """Optional (not in the default run; about 30 minutes): the cache behaviour of the thesis
    configuration itself, 256x256 pixels on Manix and Macoessix, tile 8 against scanline and
    Full, 4 spp. callgrind's cache simulator (the same as cachegrind's) counting only inside
    render_tiles, so the long load of the 242 MB volume is not simulated."""
    rows = []
    out = b.dir("img", "cachebig")
    for name in ("manix", "macoessix"):
        ds = DATASETS[name]
        vol = ensure_volume(b, name)
        for label, tile in (("tile8", 8), ("scanline", 0), ("full", 256)):
            scene = b.path("scenes", f"cachebig_{name}_{label}.yaml")
            write_scene(b, scene, name, vol, [render_entry(label, ds, width=256, height=256, spp=4,
                                                           distance=CLOSE, tile=tile,
                                                           integrator={"culling": False})], 1, out)
            log(f"cachebig: callgrind {name} 256x256x4 {label}")
            out_file = b.path("cachegrind", f"big_{name}_{label}.out")
            subprocess.run(["valgrind", "--tool=callgrind", "--cache-sim=yes", *CG_CACHES,
                            "--collect-atstart=no", "--toggle-collect=tessera::render_tiles*",
                            f"--callgrind-out-file={out_file}", b.render_exe, scene, "--quiet"],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            rows.append(cache_row(name, 256, 4, label, tile, read_cg_summary(out_file)))
    clean_images(out)
    write_csv(b.path("cachegrind_big.csv"), rows)


STUDIES = {"error": study_error, "rescore": study_rescore, "thesis": study_thesis,
           "scaling": study_scaling, "targets": study_targets, "cache": study_cache,
           "cachebig": study_cachebig}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--results", required=True)
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))))
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--only", default="data," + ",".join(k for k in STUDIES
                                                          if k not in ("rescore", "cachebig")))
    a = ap.parse_args()
    b = Bench(a.root, os.path.abspath(a.build), os.path.abspath(a.results), a.quick)
    S = settings(a.quick)
    only = a.only.split(",")
    if "data" in only:
        for name in sorted({*S["err_sets"], *S["th_sets"], *S["sc_sets"], S["cache_set"], "blobs"}):
            log(f"data: {name}: {'ok' if ensure_volume(b, name) else 'unavailable'}")
    for name, fn in STUDIES.items():
        if name in only:
            fn(b, S)
    for f in glob.glob(os.path.join(b.results, "img", "*")):
        if os.path.isdir(f) and not os.listdir(f):
            os.rmdir(f)


if __name__ == "__main__":
    main()
