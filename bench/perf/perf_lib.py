"""Shared pieces of the performance benchmarks: data sets, scene files, running tessera-render.

Standard library only (the plots are the only part that needs matplotlib). Scene files are
written as JSON, which is YAML flow syntax, so tessera-render reads them unchanged.
"""
import csv
import json
import os
import subprocess
import tempfile
import sys
import time

CLK_TCK = os.sysconf("SC_CLK_TCK")


class Bench:
    """Paths and the tools: build dir, results dir, executables."""

    def __init__(self, root, build, results, quick):
        self.root = root
        self.build = build
        self.results = results
        self.quick = quick
        self.render_exe = os.path.join(build, "bin", "tessera-render")  # every program: build/bin/
        self.synth_exe = os.path.join(build, "bin", "tessera-synth")
        self.heat_exe = os.path.join(build, "bin", "tessera-heat")
        self.rmse_exe = os.path.join(build, "bench", "perf", "tessera-rmse")
        self.data = os.path.join(results, "data")
        for d in (results, self.data):
            os.makedirs(d, exist_ok=True)

    def dir(self, *parts):
        d = os.path.join(self.results, *parts)
        os.makedirs(d, exist_ok=True)
        return d

    def path(self, *parts):
        p = os.path.join(self.results, *parts)
        os.makedirs(os.path.dirname(p), exist_ok=True)
        return p


def require_positive(ap, args, names):
    """argparse check shared by the benchmark scripts: each named integer option at least 1
    (a size, sample count or repeat count of 0 or less leaves nothing to measure)."""
    for name in names:
        v = getattr(args, name)
        if v < 1:
            ap.error(f"--{name}: at least 1 (got {v})")


def log(msg):
    print(f"[perf {time.strftime('%H:%M:%S')}] {msg}", flush=True)


def loadavg():
    return os.getloadavg()[0]


def _cpu_times():
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:]]
    return v[3] + v[4], sum(v)  # idle + iowait, total


def idle_cores(interval=1.0):
    """Cores left idle by everything else on the machine over `interval` seconds."""
    i0, t0 = _cpu_times()
    time.sleep(interval)
    i1, t1 = _cpu_times()
    return os.cpu_count() * (i1 - i0) / max(1, t1 - t0)


def wait_for_idle(max_wait, cores=1.7):
    """Before a threaded measurement: waits up to max_wait seconds for `cores` idle cores (other
    work on a shared machine steals cores from a 2-thread run). Once a wait has failed, later
    calls only look (the machine is busy for good). Returns the idle cores seen."""
    start = time.time()
    idle = idle_cores()
    while idle < cores and time.time() - start < max_wait and not _busy[0]:
        idle = idle_cores()
    if idle < cores and not _busy[0]:
        _busy[0] = True
        log(f"only {idle:.2f} idle cores after waiting {max_wait:.0f} s; measuring anyway "
            "(no more waiting in this run)")
    return idle


_busy = [False]


def heat_volume(b, path, dims):
    """Runs the heat miniapp (serial; no render fires after step 0) and dumps its field."""
    with tempfile.TemporaryDirectory() as tmp:
        cfg = os.path.join(tmp, "quiet.yaml")
        with open(cfg, "w") as f:
            f.write("tessera: {output_dir: %s}\nrenders:\n  - name: probe\n    field: temperature\n"
                    "    trigger: {every: 1000000000}\n    image: {width: 4, height: 4, spp: 1}\n"
                    "    camera: {position: [0.5, -2.0, 0.5]}\n"
                    "    transfer_function: {range: [300, 400], opacity: [[0, 0], [1, 1]]}\n"
                    "    output: {formats: [exr]}\n" % tmp)
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        subprocess.run([b.heat_exe, "--config", cfg, "--steps", str(HEAT_STEPS), "--grid",
                        *map(str, dims), "--dump", path], check=True, env=env,
                       stdout=subprocess.DEVNULL)
    return path


# ----------------------------------------------------------------------------------------------
# Data sets
# ----------------------------------------------------------------------------------------------

# Transfer functions. "blobs" keeps the thin outer shell faintly visible (value ~0.45) and the
# Gaussian blobs dense; the CT one shows skin faintly and bone opaque.
BLOBS_TF = {
    "opacity": [[0.0, 0.0], [0.15, 0.0], [0.35, 0.25], [1.0, 1.0]],
    "diffuse": "magma",
    "roughness": [[0.0, 0.6], [1.0, 0.3]],
}
SMOOTH_TF = {
    "opacity": [[0.0, 0.0], [1.0, 1.0]],
    "diffuse": "viridis",
}
# The heat miniapp's own transfer function (configs/heat.yaml), on its temperatures in K.
HEAT_TF = {
    "opacity": [[0.0, 0.0], [0.08, 0.0], [0.45, 0.25], [1.0, 1.0]],
    "diffuse": [[0.0, [0.25, 0.45, 0.95]], [0.45, [0.85, 0.45, 0.35]], [1.0, [1.0, 0.85, 0.55]]],
    "roughness": [[0.0, 0.6], [1.0, 0.3]],
}
HEAT_STEPS = 400  # 128^3 steps of the miniapp: t = 0.37 s, as its 64^3 demo after 100 steps
CT_TF = {
    "opacity": [[0.0, 0.0], [0.22, 0.0], [0.245, 0.03], [0.30, 0.03], [0.34, 0.0],
                [0.36, 0.8], [1.0, 1.0]],
    "diffuse": [[0.0, [0.8, 0.5, 0.4]], [0.3, [0.85, 0.6, 0.5]], [0.36, [0.95, 0.92, 0.85]],
                [1.0, [1.0, 1.0, 1.0]]],
    "roughness": [[0.0, 0.6], [1.0, 0.4]],
}


# The brain MRI (T1, skull-stripped, values 0 outside, range [0, 130]): the partial-volume rim
# and CSF (below ~64, u < 0.49) clear, grey matter (~70-95) translucent and pinkish, white matter
# (~100-125, u > 0.77) dense and pale, so the cortex's folds show over the white matter.
MRI_TF = {
    "opacity": [[0.0, 0.0], [0.45, 0.0], [0.55, 0.25], [0.72, 0.3], [0.8, 1.0], [1.0, 1.0]],
    "diffuse": [[0.0, [0.7, 0.4, 0.35]], [0.55, [0.8, 0.5, 0.45]], [0.72, [0.85, 0.65, 0.55]],
                [0.8, [0.95, 0.9, 0.82]], [1.0, [1.0, 0.97, 0.92]]],
    "roughness": [[0.0, 0.6], [1.0, 0.4]],
}


def synthetic(kind, dims, dtype, tf, density, value_range, note):
    # Equal spacing so that the longest axis is one world unit long whatever the resolution:
    # every resolution then has the same optical depth.
    s = 1.0 / (max(dims) - 1)
    return {"kind": kind, "dims": list(dims), "dtype": dtype, "spacing": [s, s, s], "tf": tf,
            "density": density, "range": value_range, "note": note,
            "file": f"{kind}_{dims[0]}x{dims[1]}x{dims[2]}_{dtype}.raw",
            "camera": {"azimuth": 35, "elevation": 25}}


DATASETS = {
    # Heat-like: smooth Gaussian blobs plus a thin shell and low-amplitude noise.
    "blobs": synthetic("blobs", (128, 128, 128), "float32", BLOBS_TF, 60.0, [0.0, 1.0],
                       "tessera-synth --kind blobs, 128^3 float32 (heat-like)"),
    # Smooth: the radial ramp 1 - 2r, dense in the middle, soft edge.
    "smooth": synthetic("sphere", (128, 128, 128), "float32", SMOOTH_TF, 8.0, [0.0, 1.0],
                        "tessera-synth --kind sphere, 128^3 float32 (smooth radial ramp)"),
    # The thesis sizes (Engine, Manix, Macoessix), synthetic blobs as int16 like CT data.
    "engine": synthetic("blobs", (128, 128, 64), "int16", BLOBS_TF, 60.0, [0.0, 4095.0],
                        "blobs 128x128x64 int16 (Engine's size)"),
    "manix": synthetic("blobs", (256, 230, 256), "int16", BLOBS_TF, 60.0, [0.0, 4095.0],
                       "blobs 256x230x256 int16 (Manix's size)"),
    "macoessix": synthetic("blobs", (512, 461, 512), "int16", BLOBS_TF, 60.0, [0.0, 4095.0],
                           "blobs 512x461x512 int16 (Macoessix's size)"),
    # The real heat field: tessera-heat 128^3 after HEAT_STEPS steps (--dump), float32, K.
    "heat": {**synthetic("heat", (128, 128, 128), "float32", HEAT_TF, 70.0, [300.0, 400.0],
                         f"tessera-heat --grid 128 128 128, {HEAT_STEPS} steps, float32 (K)"),
             "file": f"heat_128x128x128_{HEAT_STEPS}steps_float32.raw"},
    # Real head CT from scripts/fetch_ct.sh (mm units, Hounsfield values).
    "ct": {"kind": "ct", "dims": [256, 256, 108], "dtype": "int16",
           "spacing": [0.9570312, 0.9570312, 1.5], "tf": CT_TF, "density": 0.5,
           "range": [-1024.0, 3033.0], "file": "cranium.raw",
           "note": "Cranium head CT 256x256x108 int16 (invesalius-examples)",
           "camera": {"azimuth": 90, "elevation": 10}},
    # Real brain MRI from scripts/fetch_mri.sh (mm units, T1 intensities 0 .. 130), seen from
    # the left: the lateral view, frontal lobe on the left of the image, cerebellum lower right.
    "mri": {"kind": "mri", "dims": [301, 370, 316], "dtype": "uint8",
            "spacing": [0.5, 0.5, 0.5], "tf": MRI_TF, "density": 1.0,
            "range": [0.0, 130.0], "file": "ch2better.raw",
            "note": "Colin27 T1 brain MRI 301x370x316 uint8 (mricron-data)",
            "camera": {"azimuth": 180, "elevation": 15}},
}

# The scripts that fetch the real data sets, by kind (exit 0 ok, 3 unreachable, 1 failure).
FETCH_SCRIPTS = {"ct": "fetch_ct.sh", "mri": "fetch_mri.sh"}


def ensure_volume(b, name):
    """Generates (or fetches) the volume; returns its absolute path or None if unavailable."""
    ds = DATASETS[name]
    path = os.path.join(b.data, ds["file"])
    if os.path.exists(path):
        return path
    if ds["kind"] in FETCH_SCRIPTS:
        script = os.path.join(b.root, "scripts", FETCH_SCRIPTS[ds["kind"]])
        rc = subprocess.run(["bash", script, b.data]).returncode
        return path if rc == 0 and os.path.exists(path) else None
    d = ds["dims"]
    if ds["kind"] == "heat":
        return heat_volume(b, path, d)
    subprocess.run([b.synth_exe, path, "--dims", str(d[0]), str(d[1]), str(d[2]),
                    "--dtype", ds["dtype"], "--kind", ds["kind"]], check=True,
                   stdout=subprocess.DEVNULL)
    return path


# ----------------------------------------------------------------------------------------------
# Scenes
# ----------------------------------------------------------------------------------------------

# The core's default macrocell edge (core/include/tessera/integrator.h), written into every scene
# so that the figures do not move when the default does.
MACROCELL = 8


def render_entry(name, ds, *, width, height, spp, distance=2.0, tile=16, order="row",
                 integrator=None, target_error=0.0, seed=0, variance=False, formats=("exr",)):
    """One entry of `renders:` for data set `ds` (a DATASETS value)."""
    cam = ds["camera"]
    integ = {"scattering": "single", "shading": "hybrid", "gradient_factor": 4.0,
             "macrocell": MACROCELL, "tile": tile, "tile_order": order, "seed": seed}
    integ.update(integrator or {})
    tf = {"range": ds["range"], "density_scale": ds["density"]}
    tf.update(ds["tf"])
    image = {"width": width, "height": height, "spp": spp}
    if target_error > 0:
        image["target_error"] = target_error
    return {
        "name": name,
        "image": image,
        "camera": {"position": {"orbit": {"azimuth": cam["azimuth"], "elevation": cam["elevation"],
                                          "distance": distance}},
                   "look_at": "center", "up": [0, 0, 1], "fov": 35},
        "transfer_function": tf,
        "lights": [{"type": "rect",
                    "position": {"orbit": {"azimuth": cam["azimuth"] - 75, "elevation": 50,
                                           "distance": 3}},
                    "target": "center", "size": {"relative": 1.2},
                    "color": [1.0, 0.95, 0.9], "intensity": 6}],
        "background": {"type": "gradient", "top": [0.55, 0.65, 0.85],
                       "middle": [0.25, 0.27, 0.32], "bottom": [0.08, 0.08, 0.1]},
        "integrator": integ,
        "output": {"file": "{name}", "formats": list(formats), "variance": variance},
    }


def warmup_entry(ds):
    """A tiny first render: the volume load is charged to it, not to a measured render."""
    return render_entry("warmup", ds, width=16, height=16, spp=1)


def write_scene(b, path, name, volume_path, renders, threads, out_dir, tessera=None, dtype=None):
    """A scene file for data set `name`. `tessera`: more keys of the `tessera:` block (e.g.
    device); `dtype`: the file's dtype when it is not the data set's (a converted copy)."""
    ds = DATASETS[name]
    cfg = {
        "tessera": {"output_dir": out_dir, "threads": threads, **(tessera or {})},
        "volume": {"file": volume_path, "dims": ds["dims"], "dtype": dtype or ds["dtype"],
                   "spacing": ds["spacing"], "byte_order": "little"},
        "renders": renders,
    }
    with open(path, "w") as f:
        f.write("# written by bench/perf (JSON is YAML flow syntax)\n")
        json.dump(cfg, f, indent=1)


# ----------------------------------------------------------------------------------------------
# Running
# ----------------------------------------------------------------------------------------------

def _proc_cpu(pid):
    """CPU seconds of a live process, all its threads, or None: the scheduler's nanosecond run
    times (/proc/PID/task/*/schedstat), else user + system time in clock ticks."""
    try:
        total = 0
        for tid in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{tid}/schedstat") as f:
                total += int(f.read().split()[0])
        return total * 1e-9
    except (OSError, IndexError, ValueError):
        pass
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / CLK_TCK
    except (OSError, IndexError, ValueError):
        return None


def run_scene(b, scene_path, stats_path, extra=()):
    """Runs tessera-render on a scene file. Returns one dict per render: the --stats entry
    plus `cpu_seconds` (process CPU time from the previous render's end to this one's: prepare,
    render, resolve and write; the first render also pays for the volume load) and `load1`."""
    cmd = [b.render_exe, scene_path, "--stats", stats_path] + list(extra)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    cpu_marks, loads = [], []
    last = 0.0
    for line in proc.stdout:
        now = _proc_cpu(proc.pid)
        if now is None:
            now = last
        cpu_marks.append(now - last)
        loads.append(loadavg())
        last = now
    err = proc.stderr.read()
    if proc.wait() != 0:
        raise RuntimeError(f"tessera-render failed on {scene_path}: {err.strip()}")
    with open(stats_path) as f:
        renders = json.load(f)["renders"]
    for i, r in enumerate(renders):
        r["cpu_seconds"] = cpu_marks[i] if i < len(cpu_marks) else float("nan")
        r["load1"] = loads[i] if i < len(loads) else loadavg()
    return renders


def rmse(b, ref, images):
    """tessera-rmse: {image: {rmse_rgb, rmse_lum, rel_rmse_lum, mean_lum_ref, ref_var_lum,
    relmse_lum, ref_relvar_lum}} (bench/perf/rmse.cpp)."""
    out = subprocess.run([b.rmse_exe, ref] + list(images), check=True, capture_output=True,
                         text=True).stdout
    res = {}
    for line in out.strip().splitlines():
        p = line.split(",")
        res[p[0]] = dict(zip(["rmse_rgb", "rmse_lum", "rel_rmse_lum", "mean_lum_ref",
                              "ref_var_lum", "relmse_lum", "ref_relvar_lum"], map(float, p[1:])))
    return res


def relative_error2(b, ref, images):
    """The measured images' mean squared luminance error against the exact answer, relative to
    the reference's mean luminance squared: each image's squared RMSE against `ref` less the
    reference's own noise (its variance channel), averaged over the images. Returns (rel2,
    mean luminance of the reference)."""
    errs = rmse(b, ref, images)
    e = [errs[i] for i in images]
    err2 = sum(max(0.0, x["rmse_lum"] ** 2 - x["ref_var_lum"]) for x in e) / len(e)
    return err2 / max(1e-30, e[0]["mean_lum_ref"] ** 2), e[0]["mean_lum_ref"]


def efficiency(seconds, rel2):
    """1 / (seconds x relative error^2): equal error costs 1 / efficiency time."""
    return 1.0 / (seconds * rel2) if rel2 > 0 else float("inf")


def write_csv(path, rows, fields=None):
    if not rows:
        return
    fields = fields or list(rows[0].keys())
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    log(f"wrote {os.path.relpath(path)}")


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [{k: v if k in TEXT_KEYS else _number(v) for k, v in r.items()} for r in rows]


TEXT_KEYS = {"dataset", "config", "camera", "order", "method"}


def _number(v):
    for conv in (int, float):
        try:
            return conv(v)
        except (ValueError, TypeError):
            pass
    return v


STAT_KEYS = ["wall_seconds", "cpu_seconds", "prepare_seconds", "samples", "samples_per_second",
             "density_lookups", "free_flight_lookups", "transmittance_lookups",
             "gradient_lookups", "real_collisions", "null_collisions",
             "lookups_per_real_collision", "tiles_total", "tiles_skipped", "threads", "load1"]


def stat_row(r, **extra):
    row = dict(extra)
    row.update({k: r.get(k) for k in STAT_KEYS})
    return row


if __name__ == "__main__":
    sys.exit("perf_lib.py is a module; run bench/run_perf.sh")
