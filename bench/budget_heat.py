#!/usr/bin/env python3
"""The render budget on the heat miniapp (docs/insitu.md, "Controlling the cost").

    python3 bench/budget_heat.py [--build build] [--ranks 2] [--steps 100] [--grid 64]
                                 [--budgets 0.05 0.25 1] [--work-ms 0 50] [--ref-spp 256]
                                 [--out out/bench/budget] [--csv out/bench/budget/budget_heat.csv]

For every budget and every --work-ms (computation added to each step of the simulation), runs
`mpirun -n RANKS tessera-heat --config C --work-ms W` where C is configs/heat.yaml with
`tessera.budget` set, and once more without a budget at --ref-spp samples per pixel (the
reference: the simulation is deterministic, so its fields at each step are the same in every
run). Prints and writes to the CSV, per run:

  ratio              rendering / simulation over the whole run, as tessera-heat measures them
                     (every execute call against the simulation's own time)
  ratio_after_first  the same after the first call that rendered (whose renders measure what
                     a render costs, at min_spp, whatever the budget)
  renders, skipped   renders made, renders the budget skipped
  spp_*              samples per pixel the budget planned for the renders after the first call
  rel_rmse           mean over those renders' images of the relative RMSE of luminance against
                     the reference image of the same step and view (tessera-rmse), the
                     reference's own noise included

A benchmark, not a test: timings depend on the machine and on what else runs on it.
"""
import argparse
import csv
import os
import re
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SUMMARY = re.compile(r"tessera-heat: \d+ steps, (\d+) renders(?:, (\d+) skipped by the budget)? \((\d+) failed calls\): "
                     r"simulation ([0-9.]+) s, rendering ([0-9.]+) s(?: \(([0-9.e+-]+)x the simulation"
                     r"(?:; budget [0-9.e+-]+(?:, ([0-9.e+-]+)x after the first renders)?)?\))?")
RENDER = re.compile(r"render '(\w+)' step (\d+) \(t=[^)]*\): \d+x\d+, (\d+) spp")


def config_text(budget, spp=None):
    """configs/heat.yaml with tessera.budget set (or removed: budget None) and spp replaced."""
    text = open(os.path.join(ROOT, "configs", "heat.yaml"), encoding="utf-8").read()
    text = re.sub(r"^  budget: .*\n", "", text, flags=re.M)
    if budget is not None:
        text = re.sub(r"^(  threads: .*\n)", r"\1  budget: %s\n" % budget, text, count=1, flags=re.M)
    if spp is not None:
        text = re.sub(r"spp: \d+", "spp: %d" % spp, text)
    return text


def run_heat(args, name, text, work_ms):
    """Runs tessera-heat with config `text`; returns (summary figures, [(view, step, spp)], out dir)."""
    out = os.path.join(args.out, name)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    cfg = os.path.join(out, "config.yaml")
    with open(cfg, "w", encoding="utf-8") as f:
        f.write(text)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    env.pop("TESSERA_TEST_CLOCK", None)
    cmd = ["mpirun", "--oversubscribe", "-n", str(args.ranks), os.path.join(args.build, "bin", "tessera-heat"),
           "--config", cfg, "--steps", str(args.steps), "--grid", str(args.grid), str(args.grid), str(args.grid),
           "--work-ms", str(work_ms), "--output-dir", out]
    print("  " + " ".join(cmd), flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    log = p.stdout + p.stderr
    with open(os.path.join(out, "log.txt"), "w", encoding="utf-8") as f:
        f.write(log)
    m = SUMMARY.search(log)
    if p.returncode != 0 or not m:
        sys.exit("budget_heat: tessera-heat failed (%d):\n%s" % (p.returncode, log[-3000:]))
    renders = [(v, int(s), int(k)) for v, s, k in RENDER.findall(log)]
    figures = {
        "renders": int(m.group(1)),
        "skipped": int(m.group(2) or 0),
        "simulation_s": float(m.group(4)),
        "rendering_s": float(m.group(5)),
        "ratio": float(m.group(6)) if m.group(6) else 0.0,
        "ratio_after_first": float(m.group(7)) if m.group(7) else float("nan"),
    }
    return figures, renders, out


def rel_rmse(args, ref_dir, out_dir, renders):
    """Mean relative RMSE of luminance of the images of `renders` against the reference's."""
    rmse = os.path.join(args.build, "bench", "perf", "tessera-rmse")
    errors = []
    for view, step, _ in renders:
        name = "%s_%06d.exr" % (view, step)
        p = subprocess.run([rmse, os.path.join(ref_dir, name), os.path.join(out_dir, name)],
                           capture_output=True, text=True, check=True)
        errors.append(float(p.stdout.strip().splitlines()[-1].split(",")[3]))
    return statistics.mean(errors) if errors else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--grid", type=int, default=64)
    ap.add_argument("--budgets", nargs="+", default=["0.05", "0.25", "1"])
    ap.add_argument("--work-ms", nargs="+", type=int, default=[0, 50])
    ap.add_argument("--ref-spp", type=int, default=256)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "budget"))
    ap.add_argument("--csv", default=None)
    args = ap.parse_args()
    args.csv = args.csv or os.path.join(args.out, "budget_heat.csv")
    os.makedirs(args.out, exist_ok=True)

    print("reference: %d spp, no budget" % args.ref_spp, flush=True)
    _, _, ref_dir = run_heat(args, "reference", config_text(None, args.ref_spp), 0)
    rows = []
    for work_ms in args.work_ms:
        base = None
        for budget in ["none"] + args.budgets:
            print("budget %s, --work-ms %d" % (budget, work_ms), flush=True)
            text = config_text(None if budget == "none" else budget)
            fig, renders, out = run_heat(args, "b%s_w%d" % (budget, work_ms), text, work_ms)
            later = [r for r in renders if r[1] > 0]  # after the first call (step 0), which learns
            spp = [r[2] for r in later]
            row = dict(budget=budget, work_ms=work_ms, ranks=args.ranks, steps=args.steps, grid=args.grid, **fig,
                       spp_mean=round(statistics.mean(spp), 2) if spp else 0, spp_min=min(spp, default=0),
                       spp_max=max(spp, default=0), rel_rmse=round(rel_rmse(args, ref_dir, out, later), 4))
            rows.append(row)
            print("  ratio %.3g (%.3g after the first renders), %d renders, %d skipped, spp %s..%s (mean %s), "
                  "relative RMSE %.3f" % (row["ratio"], row["ratio_after_first"], row["renders"], row["skipped"],
                                          row["spp_min"], row["spp_max"], row["spp_mean"], row["rel_rmse"]),
                  flush=True)
    with open(args.csv, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("budget_heat: wrote " + args.csv)


if __name__ == "__main__":
    main()
