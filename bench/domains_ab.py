#!/usr/bin/env python3
"""Domains A/B (docs/BENCHMARKS.md, "Domains"): tessera-heat's rendering time with each rank's
block published through tessera_execute, as one domain through tessera_execute_domains, and
as N uneven domains (--domains-per-rank N); optionally an older tessera-heat (tessera_execute
only) as a baseline. Runs are interleaved (every variant once per round), so that a change in
the machine's load hits every variant alike; prints each variant's median and its ratio to
tessera_execute.

    python3 bench/domains_ab.py build/bin/tessera-heat [--old OLD/tessera-heat] [--ranks 2]
        [--grid 64] [--steps 10] [--reps 5] [--domains 8] [--config configs/heat.yaml]

The config's `budget` line is dropped (a budget would change the samples, not the speed) and
its output goes to a scratch folder. The time measured is the slowest rank's rendering time
that tessera-heat prints at the end (all renders of the run).
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import tempfile

SUMMARY = re.compile(r"rendering ([0-9.]+) s")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("heat", help="tessera-heat to measure")
    p.add_argument("--old", help="an older tessera-heat (tessera_execute), the baseline")
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--grid", type=int, default=64)
    p.add_argument("--steps", type=int, default=10)
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--domains", type=int, default=8, help="N of the --domains-per-rank N variant (0: none)")
    p.add_argument("--config", default=os.path.join(os.path.dirname(__file__), "..", "configs", "heat.yaml"))
    a = p.parse_args()

    scratch = tempfile.mkdtemp(prefix="domains_ab_")
    config = os.path.join(scratch, "heat.yaml")
    with open(a.config) as src, open(config, "w") as dst:
        for line in src:
            if re.match(r"^\s*budget:", line):
                continue
            dst.write(re.sub(r"output_dir: .*", "output_dir: " + os.path.join(scratch, "out"), line))

    variants = []
    if a.old:
        variants.append(("old tessera_execute", a.old, []))
    variants.append(("tessera_execute", a.heat, []))
    variants.append(("1 domain per rank", a.heat, ["--domains-per-rank", "1"]))
    if a.domains > 1:
        variants.append((f"{a.domains} domains per rank", a.heat, ["--domains-per-rank", str(a.domains)]))

    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    times = {name: [] for name, _, _ in variants}
    for rep in range(a.reps):
        for name, exe, extra in variants:
            cmd = ["mpirun", "-n", str(a.ranks), exe, "--config", config, "--grid", *[str(a.grid)] * 3,
                   "--steps", str(a.steps), *extra]
            out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout
            t = float(SUMMARY.findall(out)[-1])
            times[name].append(t)
            print(f"round {rep + 1}: {name}: {t:.3f} s", flush=True)
    shutil.rmtree(scratch, ignore_errors=True)

    base = statistics.median(times["tessera_execute"])
    print(f"\n{a.ranks} ranks, {a.grid}^3, --steps {a.steps}, medians of {a.reps} interleaved runs")
    print("| variant | median rendering s | min | max | / tessera_execute |")
    print("|---|---|---|---|---|")
    for name, _, _ in variants:
        t = times[name]
        print(f"| {name} | {statistics.median(t):.3f} | {min(t):.3f} | {max(t):.3f} | "
              f"{statistics.median(t) / base:.3f} |")


if __name__ == "__main__":
    main()
