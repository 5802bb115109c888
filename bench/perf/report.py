"""Markdown tables from the CSV files of perf.py (standard library only).

    python3 bench/perf/report.py RESULTS_DIR      -> RESULTS_DIR/report.md (and stdout)

Times: `cpu` is the render's CPU time (process CPU time from the end of the previous render to the
end of this one, less the smallest prepare time of the volume; it includes resolving the film and
writing the EXR, tens of milliseconds), which
other processes on a loaded machine inflate far less than wall time; `wall` is tessera-render's
wall_seconds. Serial studies are compared on cpu, threaded ones on wall (and cpu / wall = cores
actually obtained).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_lib import DATASETS, read_csv  # noqa: E402

# Mathai 2018, Tables 1-3 (serial) and Table 4 (TBB), seconds; 1024x1024, 20 estimates, Xeon E5.
THESIS_SERIAL = {
    "full": [44.06, 14.78, 127.52, 35.66, 289.65, 54.14],
    "2": [42.47, 13.16, 101.51, 33.91, 223.58, 46.38],
    "4": [42.91, 14.02, 105.09, 33.02, 235.10, 47.13],
    "8": [43.70, 14.28, 108.51, 34.57, 235.21, 46.62],
    "16": [44.89, 14.23, 108.82, 34.48, 240.46, 48.83],
    "32": [45.58, 14.62, 110.86, 34.73, 268.35, 53.57],
    "64": [45.62, 14.56, 112.29, 34.74, 283.83, 54.03],
    "128": [44.02, 14.71, 123.61, 35.55, 286.96, 53.10],
    "256": [45.13, 14.76, 124.40, 35.64, 287.20, 53.90],
}
THESIS_TBB = {
    "full": [5.46, 1.69, 15.21, 4.56, 35.49, 6.95],
    "64": [26.52, 8.25, 54.88, 17.16, 108.26, 23.21],
    "128": [7.78, 2.48, 20.99, 6.13, 49.14, 9.94],
    "256": [6.03, 1.92, 16.41, 5.03, 38.51, 7.89],
    "512": [5.63, 1.81, 15.38, 4.62, 36.06, 7.19],
}
THESIS_COLS = [("engine", "close"), ("engine", "far"), ("manix", "close"), ("manix", "far"),
               ("macoessix", "close"), ("macoessix", "far")]
THESIS_NAMES = {"engine": "Engine", "manix": "Manix", "macoessix": "Macoessix"}


def fmt(x, nd=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    if isinstance(x, str):
        return x
    if x == 0:
        return "0"
    if abs(x) >= 1000 or abs(x) < 0.001:
        return f"{x:.3g}"
    return f"{x:.{nd}g}" if abs(x) < 1 else f"{x:.{nd}g}" if abs(x) >= 100 else f"{x:.{nd}g}"


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(fmt(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def mean(xs):
    xs = [x for x in xs if x is not None]
    return sum(xs) / len(xs) if xs else float("nan")


def best(rows, key):
    """The fastest of repeated renders (the least disturbed by other processes)."""
    return min(rows, key=lambda r: r[key]) if rows else None


# ----------------------------------------------------------------------------------------------

def error_section(R):
    rows = read_csv(os.path.join(R, "error_vs_time.csv"))
    if not rows:
        return ""
    out = ["## Run time against error", ""]
    for name in dict.fromkeys(r["dataset"] for r in rows):
        rs = [r for r in rows if r["dataset"] == name]
        r0 = rs[0]
        out += [f"### {name}: {DATASETS[name]['note']}", "",
                f"{r0['size']}x{r0['size']} pixels, reference: delta tracking, grid majorant, "
                f"{r0['ref_spp']} spp (its own noise, {fmt(r0['ref_noise_lum'])} RMSE, is "
                "subtracted in quadrature). One thread; `cpu` = render CPU seconds. RMSE of "
                "luminance; relMSE = mean of (img - ref)^2 / (ref^2 + 0.01). "
                "Efficiency = 1 / (RMSE^2 x cpu), higher is better.", ""]
        body = []
        for r in rs:
            label = {"raymarch": f"raymarch step {r['param']}", "delta_global": "delta, global majorant",
                     "delta_grid": f"delta, grid majorant ({r['param']})",
                     "delta_grid_adaptive": f"delta grid, adaptive {r['param']}"}[r["method"]]
            eff = 1.0 / (r["rmse_lum_corrected"] ** 2 * r["render_cpu_s"]) \
                if r["rmse_lum_corrected"] > 0 and r["render_cpu_s"] > 0 else float("nan")
            body.append([label, r["spp"], r["samples"], r["render_cpu_s"], r["wall_seconds"],
                         r["rmse_lum_corrected"], r["rel_rmse_lum"], r.get("relmse_corrected"),
                         r["density_lookups"] / r["samples"], eff])
        out += [table(["method", "spp", "samples", "cpu s", "wall s", "RMSE (lum)", "RMSE / mean",
                       "relMSE", "lookups/sample", "efficiency"], body), ""]
    return "\n".join(out)


def adaptive_rows(R, metric="rmse_lum_corrected"):
    """Adaptive runs against the uniform delta-grid curve: the uniform time for the same error
    (log-log interpolation between the uniform points)."""
    rows = read_csv(os.path.join(R, "error_vs_time.csv"))
    res = []
    for name in dict.fromkeys(r["dataset"] for r in rows):
        uni = sorted([r for r in rows if r["dataset"] == name and r["method"] == "delta_grid"],
                     key=lambda r: r["render_cpu_s"])
        for a in (r for r in rows if r["dataset"] == name and r["method"] == "delta_grid_adaptive"):
            if metric not in a or a[metric] in ("", None):
                continue
            e = a[metric]
            t_u = float("nan")
            for p, q in zip(uni, uni[1:]):
                lo, hi = q[metric], p[metric]
                if lo <= e <= hi and lo > 0 and p["render_cpu_s"] > 0:
                    f = math.log(hi / e) / math.log(hi / lo)
                    t_u = math.exp(math.log(p["render_cpu_s"]) +
                                   f * (math.log(q["render_cpu_s"]) - math.log(p["render_cpu_s"])))
            res.append([name, a["param"], a["spp"], a["samples"], e, a["render_cpu_s"], t_u,
                        t_u / a["render_cpu_s"] if a["render_cpu_s"] > 0 else float("nan")])
    return res


# ----------------------------------------------------------------------------------------------

def thesis_section(R):
    rows = read_csv(os.path.join(R, "thesis_tiles.csv"))
    if not rows:
        return ""
    size = rows[0]["size"]
    out = ["## Thesis tiling study", "",
           f"Our renders: {size}x{size} pixels, 20 spp, single scattering, hybrid shading, "
           "delta tracking on the grid majorant, culling off; the fastest of the repeats. "
           "`ours` is render CPU seconds (serial) or wall seconds (TBB, 2 threads); `thesis` is "
           "Mathai 2018 at 1024x1024 on a 6-core Xeon E5. Our `Full` is one tile covering the "
           "image (all 20 estimates over the whole image in turn, the thesis' no-tiling case); "
           "`scanline` is tile 0 (one row, all estimates, then the next row). Relative columns: "
           "time / Full.", ""]

    def get(threads, ds, cam, cfg, key):
        rs = [r for r in rows if r["threads_req"] == threads and r["dataset"] == ds
              and r["camera"] == cam and r["config"] == cfg]
        r = best(rs, key)
        return r[key] if r else None

    def cfg_for(label):
        """Tiles >= the image are one tile, measured as 'full'."""
        return "full" if label.isdigit() and int(label) >= size else label

    sets = [d for d in THESIS_NAMES if any(r["dataset"] == d for r in rows)]
    for threads, thesis, key, title in ((1, THESIS_SERIAL, "render_cpu_s", "Serial (Tables 1-3)"),
                                        (2, THESIS_TBB, "wall_seconds", "TBB, 2 threads (Table 4)")):
        labels = ["full", "scanline"] + [str(t) for t in (2, 4, 8, 16, 32, 64, 128, 256, 512)
                                         if str(t) in thesis or threads == 2 and t >= 8]
        if threads == 1:
            labels += sorted({r["config"] for r in rows if r["config"].startswith("morton")},
                             key=lambda s: int(s[6:]))
        out += [f"### {title}", ""]
        for ds in sets:
            cols = [(ds, "close"), (ds, "far")]
            header = ["tile"]
            for _, cam in cols:
                header += [f"{cam}: ours s", "rel.", "thesis s", "rel."]
            body = []
            for label in labels:
                line = [label if not label.isdigit() else f"{label}x{label}" +
                        (" (= Full)" if int(label) >= size else "")]
                for _, cam in cols:
                    i = THESIS_COLS.index((ds, cam))
                    ours = get(threads, ds, cam, cfg_for(label), key)
                    full = get(threads, ds, cam, "full", key)
                    th = thesis.get(label, [None] * 6)[i]
                    line += [ours, ours / full if ours and full else None, th,
                             th / thesis["full"][i] if th else None]
                body.append(line)
            # Best reduction against Full, as in the thesis
            red = ["best reduction"]
            for _, cam in cols:
                i = THESIS_COLS.index((ds, cam))
                full = get(threads, ds, cam, "full", key)
                vals = [(get(threads, ds, cam, cfg_for(l), key), l) for l in labels if l != "full"]
                vals = [(v, l) for v, l in vals if v]
                red += [f"{100 * (1 - min(vals)[0] / full):.1f}% ({min(vals)[1]})" if full and vals
                        else "—", ""]
                red += [f"{100 * (1 - min(thesis[k][i] for k in thesis) / thesis['full'][i]):.1f}%"
                        if threads == 1 else "", ""]
            body.append(red)
            mine = [r for r in rows if r["threads_req"] == threads and r["dataset"] == ds]
            cores = mean([r["render_cpu_s"] / r["wall_seconds"] for r in mine if r["wall_seconds"] > 0])
            busy = (f"; cores obtained {cores:.2f}" if threads > 1 else "") + \
                f", load average {mean([r['load1'] for r in mine]):.1f}"
            out += [f"**{THESIS_NAMES[ds]}** ({DATASETS[ds]['note']}{busy})", "",
                    table(header, body), ""]
        # Noise: how far apart the repeats of one configuration are
        spreads = []
        for ds in sets:
            for cam in ("close", "far"):
                by = {}
                for r in rows:
                    if r["threads_req"] == threads and r["dataset"] == ds and r["camera"] == cam:
                        by.setdefault(r["config"], []).append(r[key])
                spreads += [(max(v) - min(v)) / mean(v) for v in by.values() if len(v) > 1]
        tb = [r for r in rows if r["threads_req"] == threads]
        note = (f"Repeat spread (max - min) / mean of one configuration: median "
                f"{100 * sorted(spreads)[len(spreads) // 2]:.1f}%, largest {100 * max(spreads):.1f}%. "
                if spreads else "")
        cores = [r["render_cpu_s"] / r["wall_seconds"] for r in tb if r["wall_seconds"] > 0]
        out += [note + (f"Cores obtained (render CPU / wall) {mean(cores):.2f} on average; "
                        if threads > 1 else "") +
                f"1-minute load average during the runs {mean([r['load1'] for r in tb]):.1f}.", ""]
    return "\n".join(out)


def tbb_vs_scanline_rows(R):
    rows = read_csv(os.path.join(R, "thesis_tiles.csv"))
    res = []
    for ds in dict.fromkeys(r["dataset"] for r in rows):
        for cam in ("close", "far"):
            rs = [r for r in rows if r["threads_req"] == 2 and r["dataset"] == ds and r["camera"] == cam]
            if not rs:
                continue
            by = {}
            for r in rs:
                by.setdefault(r["config"], []).append(r)
            scan = best(by.get("scanline", []), "wall_seconds")
            tiles = [c for c in by if c.isdigit() and int(c) >= 8]
            ratios = {c: best(by[c], "wall_seconds")["wall_seconds"] / scan["wall_seconds"] for c in tiles}
            cpu_ratios = {c: best(by[c], "render_cpu_s")["render_cpu_s"] /
                          best(by["scanline"], "render_cpu_s")["render_cpu_s"] for c in tiles}
            worst = max(ratios, key=ratios.get)
            res.append([ds, cam, scan["wall_seconds"],
                        ", ".join(f"{c}: {ratios[c]:.3f}" for c in sorted(tiles, key=int)),
                        ", ".join(f"{c}: {cpu_ratios[c]:.3f}" for c in sorted(tiles, key=int)),
                        f"{worst} ({ratios[worst]:.3f})"])
    return res


# ----------------------------------------------------------------------------------------------

def scaling_section(R):
    rows = read_csv(os.path.join(R, "scaling.csv"))
    if not rows:
        return "", ""
    sc, sp = [], []
    for ds in dict.fromkeys(r["dataset"] for r in rows):
        r1 = best([r for r in rows if r["dataset"] == ds and r["threads_req"] == 1], "wall_seconds")
        r2 = best([r for r in rows if r["dataset"] == ds and r["threads_req"] == 2], "wall_seconds")
        c1 = best([r for r in rows if r["dataset"] == ds and r["threads_req"] == 1], "render_cpu_s")
        c2 = best([r for r in rows if r["dataset"] == ds and r["threads_req"] == 2], "render_cpu_s")
        sc.append([ds, r1["wall_seconds"], r2["wall_seconds"], r1["wall_seconds"] / r2["wall_seconds"],
                   c1["render_cpu_s"], c2["render_cpu_s"], c1["render_cpu_s"] / c2["render_cpu_s"],
                   r2["render_cpu_s"] / r2["wall_seconds"],
                   mean([r["load1"] for r in rows if r["dataset"] == ds])])
        sps_core = c1["samples"] / c1["render_cpu_s"] if c1["render_cpu_s"] > 0 else float("nan")
        lk = c1["density_lookups"] / c1["samples"]
        sp.append([ds, DATASETS[ds]["note"], c1["samples"], sps_core,
                   r2["samples"] / r2["wall_seconds"] / 2, lk,
                   1e9 * c1["render_cpu_s"] / c1["density_lookups"] if c1["density_lookups"] else None,
                   c1["real_collisions"] / c1["samples"]])
    r0 = rows[0]
    head = (f"Close camera, {r0['size']}x{r0['size']} pixels, {r0['spp']} spp, tile 16, delta "
            "tracking on the grid, single scattering; fastest of the repeats.")
    a = ["## Thread scaling", "", head + " Speedup = wall(1) / wall(2); CPU efficiency = "
         "cpu(1) / cpu(2) (the threading overhead alone, which contention does not hide); cores "
         "obtained = render CPU / wall of the 2-thread run.", "",
         table(["data set", "wall 1 thr s", "wall 2 thr s", "speedup", "cpu 1 thr s", "cpu 2 thr s",
                "CPU efficiency", "cores obtained", "load avg"], sc), ""]
    b = ["## Samples per second", "", head + " Per core: samples / render CPU seconds with one "
         "thread; 2 threads: samples / wall / 2.", "",
         table(["data set", "volume", "samples", "samples/s/core (1 thr, cpu)",
                "samples/s/core (2 thr, wall)", "lookups/sample", "cpu ns/lookup",
                "real collisions/sample"], sp), ""]
    return "\n".join(a), "\n".join(b)


# ----------------------------------------------------------------------------------------------

def targets_section(R):
    out = ["## Targets", ""]
    mj = read_csv(os.path.join(R, "majorant.csv"))
    if mj:
        body = []
        for ds in dict.fromkeys(r["dataset"] for r in mj):
            by = {r["config"]: r for r in mj if r["dataset"] == ds}
            g = by["global"]["lookups_per_real_collision"]
            for c in [k for k in by if k.startswith("grid")] + ["global"]:
                r = by[c]
                body.append([ds, c, r["free_flight_lookups"], r["real_collisions"],
                             r["lookups_per_real_collision"],
                             g / r["lookups_per_real_collision"] if r["lookups_per_real_collision"] else None,
                             r["density_lookups"] / r["samples"], r["render_cpu_s"],
                             r["wall_seconds"], r["prepare_seconds"]])
        out += ["### Free-flight lookups per real collision (target: grid <= 1.5 and >= 4x fewer "
                "than global)", "",
                f"`gridN` = macrocells of N voxels (8 is the default); {mj[0].get('size', '')}x{mj[0].get('size', '')} pixels, 8 spp, close camera, one thread. "
                "`cpu` and `wall` are the render's; `prepare` builds the grid.", "",
                table(["data set", "majorant", "free-flight lookups", "real collisions",
                       "lookups / real collision", "global / this", "all lookups / sample",
                       "cpu s", "wall s", "prepare s"], body), ""]
    tb = tbb_vs_scanline_rows(R)
    if tb:
        out += ["### TBB tiled against TBB scanline (target: tiled <= scanline at every tile >= 8)", "",
                "Ratios wall(tile) / wall(scanline), 2 threads, fastest of the repeats; the cpu "
                "column gives the same ratio of render CPU time.", "",
                table(["data set", "camera", "scanline wall s", "wall ratio by tile", "cpu ratio by tile",
                       "worst"], tb), ""]
    cu = read_csv(os.path.join(R, "culling.csv"))
    if cu:
        on = [r for r in cu if r["config"] == "culling_on"]
        off = [r for r in cu if r["config"] == "culling_off"]
        bon, boff = best(on, "render_cpu_s"), best(off, "render_cpu_s")
        out += ["### Tile culling (target: measurably faster with empty space)", "",
                f"blobs 128^3 at 12 bounding radii, {cu[0]['size']}x{cu[0]['size']} pixels, {cu[0].get('spp', '?')} spp, "
                "tile 16, one thread; `integrator.culling` on and off; fastest of the repeats.", "",
                table(["culling", "tiles skipped / total", "cpu s", "wall s", "samples/s (wall)"],
                      [["on", f"{bon['tiles_skipped']} / {bon['tiles_total']}", bon["render_cpu_s"],
                        best(on, "wall_seconds")["wall_seconds"], best(on, "wall_seconds")["samples_per_second"]],
                       ["off", f"{boff['tiles_skipped']} / {boff['tiles_total']}", boff["render_cpu_s"],
                        best(off, "wall_seconds")["wall_seconds"], best(off, "wall_seconds")["samples_per_second"]]]),
                ""]
    ad = adaptive_rows(R)
    if ad:
        out += ["### Adaptive sampling (target: a given RMSE in less time than uniform)", "",
                "Uniform time for the same error from the uniform delta-grid curve (log-log "
                "interpolation; — when the error lies outside it). uniform / adaptive > 1 means "
                "adaptive sampling is faster.", "",
                table(["data set", "target_error", "max spp", "samples", "RMSE", "adaptive cpu s",
                       "uniform cpu s, same RMSE", "uniform / adaptive"], ad), ""]
        ad = adaptive_rows(R, "relmse_corrected")
        if ad:
            out += ["The same against relative MSE (each pixel's error relative to its value, "
                    "the quantity adaptive sampling equalises):", "",
                    table(["data set", "target_error", "max spp", "samples", "relMSE",
                           "adaptive cpu s", "uniform cpu s, same relMSE", "uniform / adaptive"], ad), ""]
    return "\n".join(out)


def cache_table(rows):
    full = {r["dataset"]: r for r in rows if r["config"].startswith("full")}
    body = [[r["dataset"], r["config"], r["Ir"], r["Drefs"], r["D1_miss_rate"] * 100,
             r["LL_miss_rate"] * 100, r["D1_misses"], r["LL_misses"], r["LL_misses_per_kIr"],
             r["est_cycles"] / full[r["dataset"]]["est_cycles"] if r["dataset"] in full else None]
            for r in rows]
    return table(["data set", "config", "instructions", "data refs", "D1 miss %", "LL miss %",
                  "D1 misses", "LL misses", "LL misses / 1000 instr", "est. time / Full"], body)


def cache_section(R):
    rows = read_csv(os.path.join(R, "cachegrind.csv"))
    if not rows:
        return ""
    r0 = rows[0]
    out = [
        "### Cache behaviour (cachegrind)", "",
        f"{r0['dataset']}, {r0['size']}x{r0['size']} pixels, {r0['spp']} spp, close camera, one "
        "thread; `valgrind --tool=cachegrind --cache-sim=yes --D1=49152,12,64 --LL=2097152,16,64` "
        "(this CPU's L1d and L2; its 105 MiB L3 is shared with other VMs and not a power of two). "
        "A 1x1, 1-spp run of the same scene (load + prepare) is subtracted, so the counts are the "
        "rendering's. Est. time = (Ir + 10 L1 misses + 100 LL misses) relative to Full, "
        "cachegrind's old rough cycle model.", "", cache_table(rows), ""]
    big = read_csv(os.path.join(R, "cachegrind_big.csv"))
    if big:
        out += ["The thesis configuration itself (`--only cachebig`): 256x256 pixels, 4 spp, close "
                "camera, same simulated caches, callgrind counting only inside `render_tiles`.", "",
                cache_table(big), ""]
    return "\n".join(out)


def main():
    R = sys.argv[1] if len(sys.argv) > 1 else "bench/results"
    scaling, sps = scaling_section(R)
    parts = [error_section(R), thesis_section(R), cache_section(R), scaling, sps, targets_section(R)]
    text = "\n".join(p for p in parts if p)
    with open(os.path.join(R, "report.md"), "w") as f:
        f.write("# Benchmark report (generated by bench/perf/report.py)\n\n" + text)
    print(text)


if __name__ == "__main__":
    main()
