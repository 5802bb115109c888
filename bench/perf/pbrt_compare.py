"""Time to equal error against pbrt-v4's CPU volpath integrator, on scenes both can express.

Issue 24 asks for Tessera's efficiency (1 / (seconds x relative error^2)) against pbrt-v4's on
the heat field (single and multiple scattering), the head CT (single) and the brain MRI
(multiple). pbrt-v4 renders a grid of densities with constant albedo and an HG phase function;
it has no transfer function, no colour per value and no gradient (surface) shading. So each
case is rendered here as the *common scene*, the same for both renderers:

- the medium: the case's extinction per voxel, sigma_t = density_scale x opacity(u) (perf_lib's
  transfer function applied to every sample), quantised to uint16 steps q (the largest
  sigma_t / 65535), as cell data over the data's box: Tessera reads the integers with a linear
  transfer function (sigma_t = q k, `association: cell`), pbrt-v4's `uniformgrid` medium the
  same integers with `scale` q (its samples sit at the cell centres of [p0, p1] too), both
  interpolating the samples trilinearly;
- grey albedo (0.8 on the heat field, 0.9 on the CT and MRI), isotropic phase (`shading: phase`);
- perf_lib's camera (orbit at 2 radii, fov 35) and rect light (a one-sided square of 1.2 radii,
  radiance [1, 0.95, 0.9] x 6), written as world coordinates for both; a constant background
  [0.25, 0.27, 0.32] in place of the gradient (pbrt-v4's infinite light takes a constant or an
  image);
- single scattering: Tessera's `scattering: single`, pbrt-v4's `maxdepth 1`; multiple: 16
  bounces both (Tessera's `max_bounces` default).

Each renderer is measured against its own reference at 16x the samples (independent samples,
other seeds, every thread), with the reference's noise removed: Tessera's from its variance
channel (as ete.py), pbrt-v4's from two half references A and B ((A - B)^2 / 4 per pixel). The
measured renders run on one thread, --reps seeds each, the fastest kept; pbrt-v4's seconds are
its process's wall time less that of a 1-sample render of the same file (the parse of the
density array and the setup), scaled to the measured sample count. Default sampler each (Tessera
`sobol`, pbrt-v4 `zsobol`), box pixel filter each.

    python3 bench/perf/pbrt_compare.py --pbrt /path/to/pbrt --build build --results DIR
        [--only heat_single,ct_single] [--size 128] [--spp 64] [--reps 3] [--skip-pbrt]

Needs numpy. The pbrt-v4 executable is the caller's (this script writes its scene files and
runs it; nothing of pbrt-v4 is part of Tessera). Benchmarks are not tests: nothing here asserts.
"""
import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from perf_lib import (DATASETS, Bench, efficiency, ensure_volume, log, relative_error2, require_positive, run_scene,  # noqa: E402
                      write_csv)

CASES = {
    "heat_single": ("heat", "single", 0.8),
    "heat_multiple": ("heat", "multiple", 0.8),
    "ct_single": ("ct", "single", 0.9),
    "ct_multiple": ("ct", "multiple", 0.9),
    "mri_single": ("mri", "single", 0.9),
    "mri_multiple": ("mri", "multiple", 0.9),
}
DEFAULT_CASES = "heat_single,heat_multiple,ct_single,mri_multiple"  # the four
BACKGROUND = [0.25, 0.27, 0.32]
LIGHT_L = [6.0, 5.7, 5.4]
MAX_BOUNCES = 16
DTYPES = {"float32": "<f4", "int16": "<i2", "uint8": "u1", "uint16": "<u2", "float64": "<f8"}


def extinction(ds, vol_path):
    """sigma_t per sample (float64, x fastest) of data set `ds` under its transfer function."""
    d = ds["dims"]
    v = np.fromfile(vol_path, dtype=DTYPES[ds["dtype"]]).astype(np.float64)
    if v.size != d[0] * d[1] * d[2]:
        raise RuntimeError(f"{vol_path}: {v.size} samples, expected {d}")
    lo, hi = ds["range"]
    u = np.clip((v - lo) / (hi - lo), 0.0, 1.0)
    xs, ys = zip(*ds["tf"]["opacity"])
    return ds["density"] * np.interp(u, xs, ys)


def geometry(ds):
    """World-space camera and light of perf_lib.render_entry over the cell box [0, dims x spacing]."""
    ext = np.array(ds["dims"], float) * np.array(ds["spacing"], float)
    center = ext / 2
    R = float(np.linalg.norm(ext)) / 2

    def orbit(az, el, dist):  # docs/config.md "Points and lengths", up = +z: e1 = +x, e2 = +y
        a, e = math.radians(az), math.radians(el)
        return center + dist * R * np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])

    cam = ds["camera"]
    eye = orbit(cam["azimuth"], cam["elevation"], 2.0)
    lpos = orbit(cam["azimuth"] - 75, 50, 3.0)
    n = (center - lpos) / np.linalg.norm(center - lpos)  # rect_light.h's frame
    ref = np.array([0, 1, 0]) if abs(n[2]) > 0.999 else np.array([0, 0, 1])
    u = np.cross(ref, n)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    h = 0.6 * R  # half of the 1.2 R side
    corners = [lpos - h * u - h * v, lpos + h * u - h * v, lpos - h * u + h * v, lpos + h * u + h * v]
    return {"ext": ext, "center": center, "R": R, "eye": eye, "light": lpos, "light_size": 2 * h,
            "corners": corners}


def tessera_entry(name, g, *, size, spp, scattering, albedo, q, seed, sampler, variance):
    integ = {"scattering": scattering, "shading": "phase", "macrocell": 8, "tile": 16, "seed": seed,
             "sampler": sampler, "max_bounces": MAX_BOUNCES}
    return {
        "name": name,
        "image": {"width": size, "height": size, "spp": spp},
        "camera": {"position": g["eye"].tolist(), "look_at": g["center"].tolist(), "up": [0, 0, 1], "fov": 35},
        "transfer_function": {"range": [0.0, 65535.0], "density_scale": q * 65535.0,
                              "opacity": [[0.0, 0.0], [1.0, 1.0]],
                              "diffuse": [[0.0, [albedo] * 3], [1.0, [albedo] * 3]]},
        "lights": [{"type": "rect", "position": g["light"].tolist(), "target": g["center"].tolist(),
                    "size": [g["light_size"], g["light_size"]], "color": [x / 6.0 for x in LIGHT_L],
                    "intensity": 6}],
        "background": {"type": "constant", "color": BACKGROUND},
        "integrator": integ,
        "output": {"file": "{name}", "formats": ["exr"], "variance": variance},
    }


def tessera_scene(path, raw, ds, renders, threads, out_dir):
    cfg = {"tessera": {"output_dir": out_dir, "threads": threads},
           "volume": {"file": raw, "dims": ds["dims"], "dtype": "uint16", "spacing": ds["spacing"],
                      "association": "cell", "byte_order": "little"},
           "renders": renders}
    with open(path, "w") as f:
        json.dump(cfg, f, indent=1)


def fmt(v):
    return " ".join(f"{x:.9g}" for x in v)


def pbrt_medium(path, k, g, ds, *, albedo, q):
    """The medium's definition (the density array k as integers, 16 per line), written once
    and Included by every scene file of the cases that share it."""
    d = ds["dims"]
    with open(path, "w") as f:
        f.write(f'MakeNamedMedium "vol" "string type" "uniformgrid" "integer nx" [{d[0]}] "integer ny" [{d[1]}] '
                f'"integer nz" [{d[2]}] "point3 p0" [0 0 0] "point3 p1" [{fmt(g["ext"])}] '
                f'"rgb sigma_a" [{fmt([1 - albedo] * 3)}] "rgb sigma_s" [{fmt([albedo] * 3)}] '
                f'"float scale" [{q:.9g}] "float g" [0]\n')
        f.write('  "float density" [\n')
        s = np.char.mod("%d", k)
        for i in range(0, len(s), 16):
            f.write(" ".join(s[i:i + 16]))
            f.write("\n")
        f.write("  ]\n")


def pbrt_scene(path, medium_path, g, *, size, spp, scattering, sampler, out):
    e = g["ext"]
    # The box, outward-facing triangles (pbrt-v4 puts "inside" on the side opposite the normal)
    P = [[0, 0, 0], [e[0], 0, 0], [e[0], e[1], 0], [0, e[1], 0],
         [0, 0, e[2]], [e[0], 0, e[2]], [e[0], e[1], e[2]], [0, e[1], e[2]]]
    tris = [0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 3, 0, 4, 3, 4, 7]
    depth = 1 if scattering == "single" else MAX_BOUNCES
    with open(path, "w") as f:
        f.write(f"LookAt {fmt(g['eye'])}  {fmt(g['center'])}  0 0 1\n")
        f.write('Camera "perspective" "float fov" [35]\n')
        f.write(f'Sampler "{sampler}" "integer pixelsamples" [{spp}]\n')
        f.write(f'Integrator "volpath" "integer maxdepth" [{depth}]\n')
        f.write('PixelFilter "box"\n')
        f.write(f'Film "rgb" "integer xresolution" [{size}] "integer yresolution" [{size}] "string filename" "{out}"\n')
        f.write("WorldBegin\n")
        f.write(f'LightSource "infinite" "rgb L" [{fmt(BACKGROUND)}]\n')
        f.write("AttributeBegin\n")
        f.write(f'  AreaLightSource "diffuse" "rgb L" [{fmt(LIGHT_L)}]\n')
        f.write(f'  Shape "bilinearmesh" "point3 P" [{" ".join(fmt(c) for c in g["corners"])}]\n')
        f.write("AttributeEnd\n")
        f.write("AttributeBegin\n")
        f.write(f'  Include "{medium_path}"\n')
        f.write('  MediumInterface "vol" ""\n  Material "interface"\n')
        f.write(f'  Shape "trianglemesh" "point3 P" [{" ".join(fmt(c) for c in P)}] '
                f'"integer indices" [{" ".join(map(str, tris))}]\n')
        f.write("AttributeEnd\n")


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.fromfile(f, dtype="<f4" if scale < 0 else ">f4")
    c = 3 if kind == b"PF" else 1
    return data.reshape(h, w, c).astype(np.float64)[::-1]


def lum(img):
    return 0.2126 * img[..., 0] + 0.7152 * img[..., 1] + 0.0722 * img[..., 2]


def run_pbrt(exe, scene, threads, spp, seed):
    cmd = [exe, "--nthreads", str(threads), "--seed", str(seed), "--spp", str(spp), "--quiet", scene]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, cwd=os.path.dirname(scene))
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--pbrt", help="the pbrt-v4 executable (required unless --skip-pbrt)")
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--results", default=os.path.join(root, "bench", "results", "pbrt"))
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--only", default=DEFAULT_CASES)
    ap.add_argument("--skip-pbrt", action="store_true", help="Tessera's side only")
    a = ap.parse_args()
    require_positive(ap, a, ["size", "reps"])
    if not a.skip_pbrt and not (a.pbrt and os.access(a.pbrt, os.X_OK)):
        ap.error(f"--pbrt: {a.pbrt!r} is not an executable (give pbrt-v4's, or --skip-pbrt)")
    if a.spp < 2:
        ap.error("--spp: at least 2 (pbrt-v4's time is measured against a 1-sample render)")
    b = Bench(root, os.path.abspath(a.build), os.path.abspath(a.results), quick=False)
    cases = [c for c in a.only.split(",") if c]
    unknown = [c for c in cases if c not in CASES]
    if unknown:
        ap.error(f"--only: unknown case(s) {', '.join(unknown)} (cases: {', '.join(CASES)})")
    threads = os.cpu_count()
    rows = []
    for case in cases:
        name, scattering, albedo = CASES[case]
        ds = DATASETS[name]
        vol = ensure_volume(b, name)
        if vol is None:
            log(f"pbrt_compare: {name} unavailable, {case} skipped")
            continue
        sig = extinction(ds, vol)
        q = float(sig.max()) / 65535.0
        k = np.rint(sig / q).astype(np.uint16)
        # Named by their content, so that a changed transfer function or data set never meets
        # a stale file of an earlier run
        tag = hashlib.sha1(k.tobytes()).hexdigest()[:12]
        raw = b.path("data", f"common_{name}_{tag}_uint16.raw")
        if not os.path.exists(raw):
            k.tofile(raw + ".part")  # renamed once whole: an interrupted run leaves no cached half
            os.replace(raw + ".part", raw)
        g = geometry(ds)
        out = b.dir("img", case)
        common = dict(size=a.size, scattering=scattering, albedo=albedo, q=q)
        # Tessera: reference and measured renders
        ref_scene = b.path("scenes", f"tessera_{case}_ref.yaml")
        tessera_scene(ref_scene, raw, ds, [tessera_entry("reference", g, spp=16 * a.spp, seed=987654321,
                                                         sampler="independent", variance=True, **common)],
                      threads, out)
        log(f"{case}: Tessera reference, {16 * a.spp} spp")
        run_scene(b, ref_scene, b.path("stats", f"tessera_{case}_ref.json"))
        entries = [tessera_entry("warmup", g, **dict(common, size=16), spp=1, seed=0, sampler="sobol",
                                 variance=False)]
        entries += [tessera_entry(f"run{r}", g, spp=a.spp, seed=r, sampler="sobol", variance=False, **common)
                    for r in range(a.reps)]
        scene = b.path("scenes", f"tessera_{case}.yaml")
        tessera_scene(scene, raw, ds, entries, 1, out)
        res = run_scene(b, scene, b.path("stats", f"tessera_{case}.json"))[1:]
        rel2_t, mean_lum = relative_error2(b, os.path.join(out, "reference.exr"),
                                           [os.path.join(out, f"run{r}.exr") for r in range(a.reps)])
        t_t = min(r["wall_seconds"] for r in res)
        eff_t = efficiency(t_t, rel2_t)
        row = {"case": case, "tessera_s": t_t, "tessera_rel_rmse": math.sqrt(rel2_t), "tessera_eff": eff_t,
               "tessera_mean_lum": mean_lum}
        log(f"{case}: Tessera {t_t:.3f} s, rel. RMSE {math.sqrt(rel2_t):.4g}, efficiency {eff_t:.4g}")
        if not a.skip_pbrt:
            medium = b.path("data", f"common_{name}_{tag}_albedo{albedo}.medium.pbrt")
            if not os.path.exists(medium):
                pbrt_medium(medium + ".part", k, g, ds, albedo=albedo, q=q)
                os.replace(medium + ".part", medium)
            pdir = b.dir("pbrt", case)
            files = {}
            for kind, sampler, s in (("refA", "independent", 8 * a.spp), ("refB", "independent", 8 * a.spp),
                                     ("run", "zsobol", a.spp), ("one", "zsobol", 1)):
                files[kind] = os.path.join(pdir, f"{kind}.pbrt")
                pbrt_scene(files[kind], medium, g, size=a.size, scattering=scattering, sampler=sampler, spp=s,
                           out=f"{kind}.pfm")
            log(f"{case}: pbrt-v4 references, 2 x {8 * a.spp} spp")
            run_pbrt(a.pbrt, files["refA"], threads, 8 * a.spp, 11)
            run_pbrt(a.pbrt, files["refB"], threads, 8 * a.spp, 22)
            A, B = read_pfm(os.path.join(pdir, "refA.pfm")), read_pfm(os.path.join(pdir, "refB.pfm"))
            ref = (lum(A) + lum(B)) / 2
            ref_var = np.mean((lum(A) - lum(B)) ** 2) / 4
            t_one = min(run_pbrt(a.pbrt, files["one"], 1, 1, 0) for _ in range(2))
            e2, times = [], []
            for r in range(a.reps):
                times.append(run_pbrt(a.pbrt, files["run"], 1, a.spp, 100 + r))
                x = lum(read_pfm(os.path.join(pdir, "run.pfm")))
                e2.append(max(0.0, float(np.mean((x - ref) ** 2)) - ref_var))
            rel2_p = (sum(e2) / len(e2)) / float(np.mean(ref)) ** 2
            t_p = (min(times) - t_one) * a.spp / (a.spp - 1)
            eff_p = efficiency(t_p, rel2_p)
            row.update({"pbrt_s": t_p, "pbrt_setup_s": t_one, "pbrt_rel_rmse": math.sqrt(rel2_p), "pbrt_eff": eff_p,
                        "ratio": eff_t / eff_p})
            log(f"{case}: pbrt-v4 {t_p:.3f} s (+{t_one:.2f} s setup), rel. RMSE {math.sqrt(rel2_p):.4g}, "
                f"efficiency {eff_p:.4g}; Tessera / pbrt-v4 {eff_t / eff_p:.2f}x")
        rows.append(row)
    write_csv(os.path.join(b.results, "pbrt_compare.csv"), rows)
    with open(os.path.join(b.results, "pbrt_compare.md"), "w") as f:
        f.write("| case | Tessera s | rel. RMSE | efficiency | pbrt-v4 s | rel. RMSE | efficiency | ratio |\n"
                "|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['case']} | {r['tessera_s']:.3f} | {r['tessera_rel_rmse']:.4g} | {r['tessera_eff']:.4g} | "
                    f"{r.get('pbrt_s', float('nan')):.3f} | {r.get('pbrt_rel_rmse', float('nan')):.4g} | "
                    f"{r.get('pbrt_eff', float('nan')):.4g} | {r.get('ratio', float('nan')):.2f} |\n")
    print(open(os.path.join(b.results, "pbrt_compare.md")).read())


if __name__ == "__main__":
    main()
