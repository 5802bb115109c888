"""PNG plots from the CSV files of perf.py (needs matplotlib; run from bench/venv).

    bench/venv/bin/python bench/perf/plot.py RESULTS_DIR
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_lib import read_csv  # noqa: E402
from report import THESIS_COLS, THESIS_NAMES, THESIS_SERIAL, THESIS_TBB, best  # noqa: E402


def save(fig, R, name):
    path = os.path.join(R, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"plot: wrote {path}")


def plot_error(R):
    rows = read_csv(os.path.join(R, "error_vs_time.csv"))
    for ds in dict.fromkeys(r["dataset"] for r in rows):
        fig, ax = plt.subplots(figsize=(6.4, 4.8))
        rs = [r for r in rows if r["dataset"] == ds]
        series = {}
        for r in rs:
            key = {"raymarch": f"raymarch step {r['param']}", "delta_global": "delta, global majorant",
                   "delta_grid": "delta, grid majorant",
                   "delta_grid_adaptive": "delta grid, adaptive"}[r["method"]]
            series.setdefault(key, []).append(r)
        for key, pts in series.items():
            pts.sort(key=lambda r: r["render_cpu_s"])
            x = [max(p["render_cpu_s"], 1e-3) for p in pts]
            y = [max(p["rmse_lum_corrected"], 1e-6) for p in pts]
            style = {"marker": "o"}
            if key.startswith("raymarch"):
                style = {"marker": ".", "linestyle": "--"}
            if key.endswith("adaptive"):
                style = {"marker": "*", "linestyle": "none", "markersize": 10}
                for p, xx, yy in zip(pts, x, y):
                    ax.annotate(f"{p['param']:g}", (xx, yy), textcoords="offset points", xytext=(4, 4),
                                fontsize=7)
            ax.plot(x, y, label=key, **style)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("render CPU time, one thread [s]")
        ax.set_ylabel("RMSE of luminance vs reference")
        ax.set_title(f"{ds}: error against run time")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        save(fig, R, f"error_vs_time_{ds}.png")


def plot_thesis(R):
    rows = read_csv(os.path.join(R, "thesis_tiles.csv"))
    if not rows:
        return
    size = rows[0]["size"]
    for threads, thesis, key, fname in ((1, THESIS_SERIAL, "render_cpu_s", "thesis_serial.png"),
                                        (2, THESIS_TBB, "wall_seconds", "thesis_tbb.png")):
        cols = [c for c in THESIS_COLS if any(r["dataset"] == c[0] for r in rows)]
        fig, axes = plt.subplots(1, len(cols), figsize=(3.2 * len(cols), 3.4), sharey=True, squeeze=False)
        for ax, (ds, cam) in zip(axes[0], cols):
            rs = [r for r in rows if r["threads_req"] == threads and r["dataset"] == ds and r["camera"] == cam]
            full = best([r for r in rs if r["config"] == "full"], key)[key]
            tiles = sorted({int(r["config"]) for r in rs if r["config"].isdigit()})
            ys = [best([r for r in rs if r["config"] == str(t)], key)[key] / full for t in tiles]
            ax.plot(tiles + [size], ys + [1.0], "o-", label="ours (row order)")
            mort = sorted({int(r["config"][6:]) for r in rs if r["config"].startswith("morton")})
            if mort:
                ax.plot(mort, [best([r for r in rs if r["config"] == f"morton{t}"], key)[key] / full
                               for t in mort], "s", label="ours (Morton)")
            scan = best([r for r in rs if r["config"] == "scanline"], key)
            if scan:
                ax.axhline(scan[key] / full, color="gray", linestyle=":", label="ours scanline")
            i = THESIS_COLS.index((ds, cam))
            tt = sorted(int(k) for k in thesis if k.isdigit())
            ax.plot(tt, [thesis[str(t)][i] / thesis["full"][i] for t in tt], "x--",
                    label="thesis (1024^2)")
            ax.set_xscale("log", base=2)
            ax.set_title(f"{THESIS_NAMES[ds]} {cam}", fontsize=9)
            ax.set_xlabel("tile edge [px]")
            ax.grid(True, alpha=0.3)
        axes[0][0].set_ylabel("time / Full")
        axes[0][0].legend(fontsize=6)
        save(fig, R, fname)


def plot_majorant(R):
    rows = read_csv(os.path.join(R, "majorant.csv"))
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for ds in dict.fromkeys(r["dataset"] for r in rows):
        by = {r["config"]: r for r in rows if r["dataset"] == ds}
        mc = sorted(int(k[4:]) for k in by if k.startswith("grid"))
        line, = ax.plot(mc, [by[f"grid{m}"]["lookups_per_real_collision"] for m in mc], "o-", label=ds)
        ax.axhline(by["global"]["lookups_per_real_collision"], color=line.get_color(), linestyle=":")
    ax.axhline(1.5, color="red", linewidth=0.8, label="target 1.5")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("macrocell edge [voxels] (dotted: global majorant)")
    ax.set_ylabel("free-flight lookups / real collision")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, R, "majorant_lookups.png")


def main():
    R = sys.argv[1] if len(sys.argv) > 1 else "bench/results"
    plot_error(R)
    plot_thesis(R)
    plot_majorant(R)


if __name__ == "__main__":
    main()
