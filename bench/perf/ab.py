#!/usr/bin/env python3
"""A/B of two tessera-render binaries on the heat, blobs and CT scenes of bench/perf.

    python3 bench/perf/ab.py OLD_EXE NEW_EXE [--build BUILD] [--results DIR] [--reps 3]
                             [--size 128] [--spp 8] [--threads 1] [--sets heat,blobs,ct]
                             [--scattering single,multiple]

Runs every scene (each set, with each `--scattering`) with the two binaries alternately
(old, new, old, new, ...), `--reps` times each, and prints per scene the best and the median
render wall time (the --stats wall_seconds: rendering only, no load or I/O) of each binary
and new / old of the medians, and the best CPU time (user + system) of the whole process
(load and prepare included, the same work for both), which a busy machine disturbs less
than wall time. Writes every run's times to RESULTS/ab.csv. The volumes are made as bench/perf makes
them (BUILD's tessera-synth and tessera-heat; the CT from scripts/fetch_ct.sh and, with
`--sets mri`, the brain MRI from scripts/fetch_mri.sh into RESULTS/data, skipped when they
cannot be fetched). Images of the two binaries must match:
the script also compares the EXR files byte for byte and says so. A benchmark, not a test.
"""
import argparse
import filecmp
import json
import os
import resource
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perf_lib as P  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--build", default="build")
    ap.add_argument("--results", default="bench/results/ab")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--spp", type=int, default=8)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--sets", default="heat,blobs,ct")
    ap.add_argument("--scattering", default="single", help="single, multiple or both (comma list)")
    a = ap.parse_args()
    P.require_positive(ap, a, ["reps", "size", "spp", "threads"])
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    b = P.Bench(root, os.path.abspath(a.build), os.path.abspath(a.results), False)
    print(f"A/B: old {a.old}, new {a.new}; {a.size}x{a.size}, {a.spp} spp, {a.threads} thread(s), "
          f"{a.reps} runs each, alternating")
    print(f"{'scene':<14} {'old best':>8} {'new best':>8} {'old med':>8} {'new med':>8} {'med n/o':>8} "
          f"{'old cpu':>8} {'new cpu':>8}  images")
    rows = []
    for name in a.sets.split(","):
        vol = P.ensure_volume(b, name)
        if vol is None:
            print(f"{name:<14} skipped (volume unavailable)")
            continue
        ds = P.DATASETS[name]
        for scattering in a.scattering.split(","):
            scene = f"{name}_{scattering}"
            out = {}
            scenes = {}
            for tag in ("old", "new"):
                out[tag] = b.dir("out", scene, tag)
                scenes[tag] = os.path.join(b.results, f"{scene}_{tag}.yaml")
                P.write_scene(b, scenes[tag], name, vol,
                              [P.warmup_entry(ds),
                               P.render_entry("ab", ds, width=a.size, height=a.size, spp=a.spp,
                                              integrator={"scattering": scattering})],
                              a.threads, out[tag])
            walls = {"old": [], "new": []}
            cpu = {"old": float("inf"), "new": float("inf")}
            for rep in range(a.reps):
                for tag, exe in (("old", a.old), ("new", a.new)):
                    stats = os.path.join(b.results, f"{scene}_{tag}.json")
                    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
                    subprocess.run([exe, scenes[tag], "--render", "ab", "--stats", stats, "--quiet"],
                                   check=True, stdout=subprocess.DEVNULL)
                    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
                    cpu[tag] = min(cpu[tag], r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime)
                    with open(stats) as f:
                        st = json.load(f)
                    st = st[0] if isinstance(st, list) else st
                    st = st.get("renders", [st])[0] if isinstance(st, dict) and "renders" in st else st
                    walls[tag].append(float(st["wall_seconds"]))
                    rows.append({"scene": scene, "binary": tag, "run": rep, "wall_seconds": walls[tag][-1],
                                 "load1": P.loadavg()})
            same = filecmp.cmp(os.path.join(out["old"], "ab.exr"), os.path.join(out["new"], "ab.exr"),
                               shallow=False)
            med = {tag: statistics.median(walls[tag]) for tag in walls}
            print(f"{scene:<14} {min(walls['old']):8.3f} {min(walls['new']):8.3f} {med['old']:8.3f} "
                  f"{med['new']:8.3f} {med['new'] / med['old']:8.3f} {cpu['old']:8.3f} {cpu['new']:8.3f}  "
                  f"{'identical' if same else 'DIFFER'}")
    P.write_csv(os.path.join(b.results, "ab.csv"), rows)

if __name__ == "__main__":
    main()
