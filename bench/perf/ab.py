#!/usr/bin/env python3
"""A/B of two tessera-render binaries on the heat, blobs and CT scenes of bench/perf.

    python3 bench/perf/ab.py OLD_EXE NEW_EXE [--build BUILD] [--results DIR] [--reps 3]
                             [--size 128] [--spp 8] [--threads 1] [--sets heat,blobs,ct]

Runs every scene with the two binaries alternately (old, new, old, new, ...), `--reps` times
each, and prints per scene the best render wall time (the --stats wall_seconds: rendering
only, no load or I/O) of each binary and new / old, and the best CPU time (user + system) of
the whole process (load and prepare included, the same work for both), which a busy machine
disturbs less than wall time. The volumes are made as bench/perf makes
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
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    b = P.Bench(root, os.path.abspath(a.build), os.path.abspath(a.results), False)
    print(f"A/B: old {a.old}, new {a.new}; {a.size}x{a.size}, {a.spp} spp, {a.threads} thread(s), "
          f"best of {a.reps}, alternating")
    print(f"{'scene':<8} {'old s':>8} {'new s':>8} {'new/old':>8} {'old cpu':>8} {'new cpu':>8} "
          f"{'new/old':>8}  images")
    for name in a.sets.split(","):
        vol = P.ensure_volume(b, name)
        if vol is None:
            print(f"{name:<8} skipped (volume unavailable)")
            continue
        ds = P.DATASETS[name]
        out = {}
        scenes = {}
        for tag in ("old", "new"):
            out[tag] = b.dir("out", name, tag)
            scenes[tag] = os.path.join(b.results, f"{name}_{tag}.yaml")
            P.write_scene(b, scenes[tag], name, vol,
                          [P.warmup_entry(ds),
                           P.render_entry("ab", ds, width=a.size, height=a.size, spp=a.spp)],
                          a.threads, out[tag])
        best = {"old": float("inf"), "new": float("inf")}
        cpu = dict(best)
        for _ in range(a.reps):
            for tag, exe in (("old", a.old), ("new", a.new)):
                stats = os.path.join(b.results, f"{name}_{tag}.json")
                r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
                subprocess.run([exe, scenes[tag], "--render", "ab", "--stats", stats, "--quiet"],
                               check=True, stdout=subprocess.DEVNULL)
                r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu[tag] = min(cpu[tag], r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime)
                with open(stats) as f:
                    st = json.load(f)
                st = st[0] if isinstance(st, list) else st
                st = st.get("renders", [st])[0] if isinstance(st, dict) and "renders" in st else st
                best[tag] = min(best[tag], float(st["wall_seconds"]))
        same = filecmp.cmp(os.path.join(out["old"], "ab.exr"), os.path.join(out["new"], "ab.exr"),
                           shallow=False)
        print(f"{name:<8} {best['old']:8.3f} {best['new']:8.3f} {best['new'] / best['old']:8.3f} "
              f"{cpu['old']:8.3f} {cpu['new']:8.3f} {cpu['new'] / cpu['old']:8.3f}  "
              f"{'identical' if same else 'DIFFER'}")


if __name__ == "__main__":
    main()
