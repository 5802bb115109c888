"""The GPU against the CPU at equal error (issue 42): reads the ete.csv of a CPU run and of one
or more GPU runs of bench/perf/ete.py (the same cases, size and references: --reference-dir)
and writes a markdown table per GPU run:

    case | CPU spp, s, rel. RMSE | GPU spp, s, rel. RMSE | speedup at equal error | GPU M samples/s | GPU M lookups/s

The speedup at equal error is eff_gpu / eff_cpu, efficiency = 1 / (seconds x rel. error^2):
the CPU's time to reach an error over the GPU's time to reach the same error, each
extrapolated from its own run by time ~ samples ~ 1/error^2. Where the two runs took the same
spp, the plain time ratio is given too (the same estimator at the same spp reaches the same
error: no extrapolation, the GPU's fixed costs per render included). Nothing here asserts.

    python3 bench/perf/ete_compare.py CPU/ete.csv GPU/ete.csv [GPU2/ete.csv ...] [--out FILE.md]
                                      [--cpu-name "2 cores"]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_lib import read_csv  # noqa: E402


def fmt(v, spec):
    return format(v, spec) if isinstance(v, (int, float)) else (str(v) if v not in (None, "") else "-")


def table(cpu_rows, gpu_rows, cpu_path, gpu_path, cpu_name):
    cpu = {r["case"]: r for r in cpu_rows}
    g0 = gpu_rows[0] if gpu_rows else {}
    c0 = cpu_rows[0] if cpu_rows else {}
    lines = [f"GPU: {g0.get('device', '?')} ({gpu_path}); CPU: {c0.get('device', '?')}, "
             f"{c0.get('threads', '?')} thread(s), {cpu_name} ({cpu_path}).", "",
             "| case | CPU spp | CPU s | CPU rel. RMSE | GPU spp | GPU s | GPU rel. RMSE | "
             "speedup at equal error (eff. ratio) | time ratio at equal spp | GPU M samples/s | "
             "GPU M lookups/s | CPU load |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for g in gpu_rows:
        c = cpu.get(g["case"])
        if c is None:
            lines.append(f"| {g['case']} | - | - | - | {g['spp']} | {fmt(g['seconds'], '.4g')} | "
                         f"{fmt(g['rel_rmse'], '.4g')} | (no CPU row) | - | "
                         f"{fmt(g['samples_per_s'] / 1e6, '.4g')} | {fmt(g['mlookups_per_s'], '.4g')} | - |")
            continue
        if c.get("size") != g.get("size"):
            lines.append(f"| {g['case']} | sizes differ: CPU {c.get('size')}, GPU {g.get('size')} | | | | | | | | | | |")
            continue
        speedup = g["efficiency"] / c["efficiency"] if c["efficiency"] > 0 else float("nan")
        same_spp = (f"{c['seconds'] / g['seconds']:.4g}" if c["spp"] == g["spp"] and g["seconds"] > 0 else "-")
        lines.append(f"| {g['case']} | {c['spp']} | {fmt(c['seconds'], '.4g')} | {fmt(c['rel_rmse'], '.4g')} | "
                     f"{g['spp']} | {fmt(g['seconds'], '.4g')} | {fmt(g['rel_rmse'], '.4g')} | "
                     f"**{speedup:.4g}** | {same_spp} | {fmt(g['samples_per_s'] / 1e6, '.4g')} | "
                     f"{fmt(g['mlookups_per_s'], '.4g')} | {fmt(c.get('load1'), '.2f')} |")
    refs = {(g.get("reference"), c.get("reference")) for g in gpu_rows for c in [cpu.get(g["case"], {})]}
    if any(gr == "own" for gr, _ in refs):
        lines += ["", "Note: the GPU run rendered its own references (not --reference-dir): the two "
                  "errors are against different references of the same definition."]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cpu_csv")
    ap.add_argument("gpu_csv", nargs="+")
    ap.add_argument("--out", default=None, help="write the markdown here too")
    ap.add_argument("--cpu-name", default="this machine", help="words for the CPU in the table's caption")
    a = ap.parse_args()
    cpu_rows = read_csv(a.cpu_csv)
    if not cpu_rows:
        sys.exit(f"ete_compare.py: {a.cpu_csv}: no rows")
    out = []
    for path in a.gpu_csv:
        rows = read_csv(path)
        if not rows:
            out.append(f"{path}: no rows (the GPU run did not finish a case)\n")
            continue
        out.append(table(cpu_rows, rows, a.cpu_csv, path, a.cpu_name))
    text = "\n".join(out)
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
