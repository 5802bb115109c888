"""Time to equal error (issue 24's yardstick): for each case, a reference of Tessera's own at
16x the samples (another seed, every thread), then the measured render at `--spp` on one thread,
`--reps` times (interleaved over the cases; the fastest render kept). Prints and writes
(ete.csv, ete.md):

- render seconds (the fastest, wall) and the error: RMSE of luminance against the reference,
  its own noise removed (the reference's per-pixel variance of the mean), relative to the
  reference's mean luminance. The reference takes independent samples (integrator.sampler),
  whose per-pixel variance is an honest estimate of its mean's (a low-discrepancy one's would
  overstate it, and so remove too much);
- efficiency = 1 / (seconds x relative error^2): samples spent per unit of error^2, the figure
  that two estimators or two kernels compare at (equal error means 1/efficiency time);
- lookups per sample and million lookups per second per core (the renderer's achieved rate,
  to read beside bench/lookup's ceiling).

    python3 bench/perf/ete.py --build build --results bench/results/ete [--size 128] [--spp 64]
                              [--reps 3] [--only heat_single,ct_single] [--label NAME]
                              [--set KEY=VALUE ...] [--threads 1] [--device cpu|cuda]
                              [--cuda-device N] [--warmup N] [--ref-spp N]
                              [--reference-dir DIR] [--data DIR] [--field-dtype native|float32]

Cases: the heat miniapp's field (single and multiple scattering), the head CT of
scripts/fetch_ct.sh and the brain MRI of scripts/fetch_mri.sh (each single and multiple
scattering; a case whose data cannot be fetched is skipped). `--label` names a row set (e.g. the
commit) so that several runs' CSVs compare. `--set` gives an integrator key (docs/config.md) to
the measured renders and the reference alike, to measure an estimator's setting without
editing the script (e.g. `--set rr_depth=1`). Benchmarks are not tests: nothing here asserts.

The GPU against the CPU (issue 42; docs/BENCHMARKS.md, "GPU against the CPU (issue 42)"):

- `--threads N` (default 1): tessera.threads of the measured renders (the reference always
  takes every thread). The issue's CPU figure is `--threads 2`, this machine's two cores.
- `--device cpu|cuda` (tessera.device, tessera.cuda_device with `--cuda-device`): where the
  measured renders run. Left out, the scene names no device: the renderer's default, which in a
  CPU-only build (build/) is the CPU; give `--device cpu` to a CUDA build's renderer. GPU renders
  are fast, so they may take more samples (`--spp`): the figure compared is the efficiency, and
  the time ratio at equal error is eff_gpu / eff_cpu (bench/perf/ete_compare.py).
- `--warmup N` (default 1 with `--device cuda`, else 0): full-size renders before the measured
  ones in the same process, not measured (the first CUDA context and module load cost ~0.3 s);
  the 16x16 warmup entry that takes the volume load is always there.
- `--ref-spp N` (default 16 x `--spp`): the reference's samples (independent sampler, seed
  987654321, every thread, on the measured renders' device). `--reference-dir DIR` renders no
  reference but reads DIR/<case>/reference.exr (and its reference.json, which says how it was
  made) from an earlier run, e.g. a CPU run's RESULTS/img, so that GPU and CPU compare to the
  same reference. A reference of at least 16x the measured samples keeps its own noise (which
  is subtracted) small.
- `--data DIR` (default RESULTS/data): where the volumes are (scripts/gpu_bench_data.sh packs
  them for a machine without network). `--field-dtype float32` renders a float32 copy of an
  integer volume (written once beside it as NAME_float32.raw; every int16 and uint8 value is a
  float32 exactly, so the field and the image's expectation are the same), for a GPU backend
  that refuses integer fields (docs/gpu.md).

The CSV gains the device (the --stats "device" when the renderer writes it), the bytes copied
to and from the device, samples/s and the 1-minute load average during the best render.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_lib import (DATASETS, Bench, efficiency, ensure_volume, loadavg, log, relative_error2, require_positive,  # noqa: E402
                      render_entry, run_scene, warmup_entry, write_csv, write_scene)

CASES = {
    "heat_single": ("heat", "single"),
    "heat_multiple": ("heat", "multiple"),
    "ct_single": ("ct", "single"),
    "ct_multiple": ("ct", "multiple"),
    "mri_single": ("mri", "single"),
    "mri_multiple": ("mri", "multiple"),
}
REF_SEED = 987654321
# Integer dtypes whose every value a float32 holds exactly: (array typecode, numpy dtype)
EXACT_IN_FLOAT32 = {"uint8": ("B", "<u1"), "int16": ("h", "<i2"), "uint16": ("H", "<u2")}


def float32_copy(path, dtype):
    """A float32 copy of an integer volume, written once beside it (NAME_float32.raw): the same
    values exactly, so the same field. numpy when there is one, else the standard library."""
    out = os.path.splitext(path)[0] + "_float32.raw"
    if os.path.exists(out) and os.path.getmtime(out) >= os.path.getmtime(path):
        return out
    code, np_dtype = EXACT_IN_FLOAT32[dtype]
    tmp = out + ".tmp"
    try:
        import numpy as np
        np.fromfile(path, dtype=np_dtype).astype("<f4").tofile(tmp)
    except ImportError:
        import array
        src = array.array(code)
        with open(path, "rb") as f:
            src.frombytes(f.read())
        if sys.byteorder != "little":
            src.byteswap()
        dst = array.array("f", src)
        if sys.byteorder != "little":
            dst.byteswap()
        with open(tmp, "wb") as f:
            dst.tofile(f)
    os.replace(tmp, out)
    log(f"ete: {os.path.basename(path)} ({dtype}) -> {os.path.basename(out)} (float32, the same values)")
    return out


def reference_of(a, case, info):
    """The reference EXR of `case` from --reference-dir, after checking that its reference.json
    (when there is one) describes the same image: size, data set, integrator keys."""
    ref = os.path.join(a.reference_dir, case, "reference.exr")
    if not os.path.exists(ref):
        raise RuntimeError(f"--reference-dir: {ref} not found (a run of ete.py writes RESULTS/img/<case>/reference.exr)")
    meta_path = os.path.join(a.reference_dir, case, "reference.json")
    if not os.path.exists(meta_path):
        log(f"ete/{case}: {meta_path} missing: the reference is taken as is (its size, spp and settings unchecked)")
        return ref, {"spp": ""}
    with open(meta_path) as f:
        meta = json.load(f)
    for key in ("size", "dataset", "integrator"):
        if meta.get(key) != info[key]:
            raise RuntimeError(f"--reference-dir: {meta_path} has {key} {meta.get(key)!r}, this run {info[key]!r}")
    return ref, meta


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--results", default=os.path.join(root, "bench", "results", "ete"))
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--only", default="")
    ap.add_argument("--label", default="")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="an integrator key for the measured renders and the reference alike, e.g. "
                         "rr_depth=1 or shadow=delta (repeatable; VALUE read as JSON, else as a string)")
    ap.add_argument("--threads", type=int, default=1,
                    help="tessera.threads of the measured renders (default 1; 0 = every core)")
    ap.add_argument("--device", choices=["cpu", "cuda"], default=None,
                    help="tessera.device of the measured renders and of a reference rendered here "
                         "(default: no key, the renderer's default: the CPU in a CPU-only build)")
    ap.add_argument("--cuda-device", type=int, default=None, help="tessera.cuda_device (default: no key)")
    ap.add_argument("--warmup", type=int, default=None,
                    help="full-size renders before the measured ones, not measured (default 1 with "
                         "--device cuda, else 0)")
    ap.add_argument("--ref-spp", type=int, default=None, help="the reference's samples per pixel (default 16 x --spp)")
    ap.add_argument("--reference-dir", default=None,
                    help="read DIR/<case>/reference.exr (an earlier run's RESULTS/img) instead of rendering one")
    ap.add_argument("--data", default=None, help="where the volumes are (default RESULTS/data)")
    ap.add_argument("--rmse", default=None, help="tessera-rmse (default BUILD/bench/perf/tessera-rmse)")
    ap.add_argument("--field-dtype", choices=["native", "float32"], default="native",
                    help="float32: render a float32 copy of an integer volume (the same values)")
    a = ap.parse_args()
    require_positive(ap, a, ["size", "spp", "reps"])
    if a.threads < 0:
        ap.error(f"--threads: 0 (every core) or more (got {a.threads})")
    warmup = a.warmup if a.warmup is not None else (1 if a.device == "cuda" else 0)
    if warmup < 0:
        ap.error(f"--warmup: 0 or more (got {warmup})")
    ref_spp = a.ref_spp if a.ref_spp is not None else 16 * a.spp
    if ref_spp < 1:
        ap.error(f"--ref-spp: at least 1 (got {ref_spp})")
    if a.reference_dir:
        a.reference_dir = os.path.abspath(a.reference_dir)
    b = Bench(root, os.path.abspath(a.build), os.path.abspath(a.results), quick=False)
    if a.rmse:
        b.rmse_exe = os.path.abspath(a.rmse)
    if a.data:
        b.data = os.path.abspath(a.data)
        os.makedirs(b.data, exist_ok=True)
    only = [c for c in a.only.split(",") if c]
    unknown = [c for c in only if c not in CASES]
    if unknown:
        ap.error(f"--only: unknown case(s) {', '.join(unknown)} (cases: {', '.join(CASES)})")
    cases = [c for c in CASES if not only or c in only]
    extra = {}
    for kv in a.set:
        key, eq, value = kv.partition("=")
        if not eq or not key:
            ap.error(f"--set: {kv!r} is not KEY=VALUE")
        if key in ("scattering", "seed", "sampler"):
            ap.error(f"--set: {key} is set by the script itself")
        try:
            extra[key] = json.loads(value)
        except ValueError:
            extra[key] = value
    device_keys = {}
    if a.device:
        device_keys["device"] = a.device
    if a.cuda_device is not None:
        device_keys["cuda_device"] = a.cuda_device
    rows = []
    for case in cases:
        name, scattering = CASES[case]
        vol = ensure_volume(b, name)
        if vol is None:
            log(f"ete: {name} unavailable, {case} skipped")
            continue
        ds = DATASETS[name]
        dtype = ds["dtype"]
        if a.field_dtype == "float32" and dtype in EXACT_IN_FLOAT32:
            vol, dtype = float32_copy(vol, dtype), "float32"
        out = b.dir("img", case)
        integ = dict(extra, scattering=scattering)
        load_start = loadavg()
        info = {"case": case, "dataset": name, "size": a.size, "integrator": integ}
        # The reference: an earlier run's, or 16x the samples, another seed, every thread, with its variance
        if a.reference_dir:
            ref, meta = reference_of(a, case, info)
            ref_label, ref_spp_row = a.reference_dir, meta.get("spp", "")
            log(f"ete/{case}: reference {ref} ({ref_spp_row} spp, {meta.get('device', '?')})")
        else:
            ref = os.path.join(out, "reference.exr")
            ref_scene = b.path("scenes", f"ete_{case}_ref.yaml")
            write_scene(b, ref_scene, name, vol, [render_entry("reference", ds, width=a.size, height=a.size,
                        spp=ref_spp, integrator=dict(integ, seed=REF_SEED, sampler="independent"),
                        variance=True)], 0, out, tessera=device_keys, dtype=dtype)
            log(f"ete/{case}: reference {a.size}x{a.size}, {ref_spp} spp")
            ref_stats = run_scene(b, ref_scene, b.path("stats", f"ete_{case}_ref.json"))[0]
            with open(os.path.join(out, "reference.json"), "w") as f:
                json.dump(dict(info, spp=ref_spp, seed=REF_SEED, sampler="independent", field_dtype=dtype,
                               device=ref_stats.get("device", a.device or "default"),
                               seconds=ref_stats["wall_seconds"]), f, indent=1)
            ref_label, ref_spp_row = "own", ref_spp
        # The measured renders: `threads` threads, `reps` times in one process (the volume loads
        # once), after the warmup entry (the volume load) and `warmup` full-size renders
        full = dict(width=a.size, height=a.size, spp=a.spp)
        entries = ([warmup_entry(ds)]
                   + [render_entry(f"warm{w}", ds, **full, integrator=dict(integ, seed=1000 + w)) for w in range(warmup)]
                   + [render_entry(f"run{r}", ds, **full, integrator=dict(integ, seed=r)) for r in range(a.reps)])
        scene = b.path("scenes", f"ete_{case}.yaml")
        write_scene(b, scene, name, vol, entries, a.threads, out, tessera=device_keys, dtype=dtype)
        res = run_scene(b, scene, b.path("stats", f"ete_{case}.json"))[1 + warmup:]
        # Noise of the reference removed (at 16x the samples, 1/16 of the measured render's variance)
        rel2, _ = relative_error2(b, ref, [os.path.join(out, f"run{r}.exr") for r in range(a.reps)])
        best = min(res, key=lambda r: r["wall_seconds"])
        t = best["wall_seconds"]
        samples = best["samples"]
        row = {"label": a.label, "case": case, "device": best.get("device", a.device or "default"),
               "threads": a.threads, "size": a.size, "spp": a.spp, "ref_spp": ref_spp_row, "reference": ref_label,
               "field_dtype": dtype, "seconds": t, "prepare_seconds": best.get("prepare_seconds", ""),
               "rel_rmse": rel2 ** 0.5, "efficiency": efficiency(t, rel2), "samples_per_s": samples / t,
               "lookups_per_sample": best["density_lookups"] / samples,
               "mlookups_per_s": best["density_lookups"] / t / 1e6,
               "lookups_per_real_collision": best["lookups_per_real_collision"],
               "bytes_to_device": best.get("bytes_to_device", ""), "bytes_to_host": best.get("bytes_to_host", ""),
               "seconds_all": " ".join(f"{r['wall_seconds']:.4g}" for r in res),
               "load1_start": load_start, "load1": best["load1"]}
        rows.append(row)
        log(f"ete/{case}: {t:.4g} s, rel. RMSE {row['rel_rmse']:.4g}, efficiency {row['efficiency']:.4g}, "
            f"{row['samples_per_s'] / 1e6:.3g} M samples/s, {row['lookups_per_sample']:.2f} lookups/sample, "
            f"{row['mlookups_per_s']:.2f} M lookups/s ({row['device']}, load {row['load1']:.2f})")
    write_csv(os.path.join(b.results, "ete.csv"), rows)
    with open(os.path.join(b.results, "ete.md"), "w") as f:
        f.write("| case | device | threads | spp | s | rel. RMSE | efficiency 1/(s err^2) | M samples/s | "
                "lookups/sample | M lookups/s | load |\n|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['case']} | {r['device']} | {r['threads']} | {r['spp']} | {r['seconds']:.4g} | "
                    f"{r['rel_rmse']:.4g} | {r['efficiency']:.4g} | {r['samples_per_s'] / 1e6:.3g} | "
                    f"{r['lookups_per_sample']:.2f} | {r['mlookups_per_s']:.2f} | {r['load1']:.2f} |\n")
    print(open(os.path.join(b.results, "ete.md")).read())


if __name__ == "__main__":
    try:
        main()
    except RuntimeError as e:  # a render that failed (its error names the scene file and key)
        sys.exit(f"ete.py: {e}")
