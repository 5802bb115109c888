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
                              [--set KEY=VALUE ...]

Cases: the heat miniapp's field (single and multiple scattering), the head CT of
scripts/fetch_ct.sh and the brain MRI of scripts/fetch_mri.sh (each single and multiple
scattering; a case whose data cannot be fetched is skipped). `--label` names a row set (e.g. the
commit) so that several runs' CSVs compare. `--set` gives an integrator key (docs/config.md) to
the measured renders and the reference alike, to measure an estimator's setting without
editing the script (e.g. `--set rr_depth=1`). Benchmarks are not tests: nothing here asserts.
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_lib import (DATASETS, Bench, efficiency, ensure_volume, log, relative_error2, require_positive, render_entry,  # noqa: E402
                      run_scene, warmup_entry, write_csv, write_scene)

CASES = {
    "heat_single": ("heat", "single"),
    "heat_multiple": ("heat", "multiple"),
    "ct_single": ("ct", "single"),
    "ct_multiple": ("ct", "multiple"),
    "mri_single": ("mri", "single"),
    "mri_multiple": ("mri", "multiple"),
}


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
    a = ap.parse_args()
    require_positive(ap, a, ["size", "spp", "reps"])
    b = Bench(root, os.path.abspath(a.build), os.path.abspath(a.results), quick=False)
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
    rows = []
    for case in cases:
        name, scattering = CASES[case]
        vol = ensure_volume(b, name)
        if vol is None:
            log(f"ete: {name} unavailable, {case} skipped")
            continue
        ds = DATASETS[name]
        out = b.dir("img", case)
        integ = dict(extra, scattering=scattering)
        # The reference: 16x the samples, another seed, every thread, with its variance
        ref_scene = b.path("scenes", f"ete_{case}_ref.yaml")
        write_scene(b, ref_scene, name, vol, [render_entry("reference", ds, width=a.size, height=a.size,
                    spp=16 * a.spp, integrator=dict(integ, seed=987654321, sampler="independent"),
                    variance=True)], 0, out)
        log(f"ete/{case}: reference {a.size}x{a.size}, {16 * a.spp} spp")
        run_scene(b, ref_scene, b.path("stats", f"ete_{case}_ref.json"))
        # The measured renders: one thread, `reps` times in one process (the volume loads once)
        entries = [warmup_entry(ds)] + [render_entry(f"run{r}", ds, width=a.size, height=a.size, spp=a.spp,
                                                     integrator=dict(integ, seed=r)) for r in range(a.reps)]
        scene = b.path("scenes", f"ete_{case}.yaml")
        write_scene(b, scene, name, vol, entries, 1, out)
        res = run_scene(b, scene, b.path("stats", f"ete_{case}.json"))[1:]
        # Noise of the reference removed (it has 1/16 of the measured render's variance)
        rel2, _ = relative_error2(b, os.path.join(out, "reference.exr"),
                                  [os.path.join(out, f"run{r}.exr") for r in range(a.reps)])
        best = min(res, key=lambda r: r["wall_seconds"])
        t = best["wall_seconds"]
        samples = best["samples"]
        row = {"label": a.label, "case": case, "size": a.size, "spp": a.spp, "seconds": t,
               "rel_rmse": rel2 ** 0.5, "efficiency": efficiency(t, rel2),
               "lookups_per_sample": best["density_lookups"] / samples,
               "mlookups_per_s": best["density_lookups"] / t / 1e6,
               "lookups_per_real_collision": best["lookups_per_real_collision"]}
        rows.append(row)
        log(f"ete/{case}: {t:.3f} s, rel. RMSE {row['rel_rmse']:.4g}, efficiency {row['efficiency']:.4g}, "
            f"{row['lookups_per_sample']:.2f} lookups/sample, {row['mlookups_per_s']:.2f} M lookups/s")
    write_csv(os.path.join(b.results, "ete.csv"), rows)
    with open(os.path.join(b.results, "ete.md"), "w") as f:
        f.write("| case | s | rel. RMSE | efficiency 1/(s err^2) | lookups/sample | M lookups/s |\n|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['case']} | {r['seconds']:.3f} | {r['rel_rmse']:.4g} | {r['efficiency']:.4g} | "
                    f"{r['lookups_per_sample']:.2f} | {r['mlookups_per_s']:.2f} |\n")
    print(open(os.path.join(b.results, "ete.md")).read())


if __name__ == "__main__":
    try:
        main()
    except RuntimeError as e:  # a render that failed (its error names the scene file and key)
        sys.exit(f"ete.py: {e}")
