#!/usr/bin/env python3
"""Checks that docs/config.md opens with the smallest config and that it makes a real picture.

    check_minimal_config.py REPO_DIR BIN_DIR

* The first runnable block of docs/config.md (check_docs.py's conventions) is a ```yaml block
  holding nothing but `renders: [{field: NAME}]`: a render from a field name alone.
* The first ```sh block after it renders such a config (a line `renders: [{field: NAME}]`
  beside the `volume:`) with tessera-render. It is run as
  check_docs.py runs sh blocks (scratch folder, programs on PATH), with tessera-render at
  96x96 pixels, 8 spp, and every PNG it writes under out/ must be a picture, not a flat
  image: the luminance of its pixels (8-bit, as written) has a standard deviation of at
  least MIN_STDDEV, at least MIN_SHARE of the pixels are brighter than BRIGHT and at least
  MIN_SHARE darker than DARK.
Prints what it measured; exits 1 on any failure.
"""
import glob
import os
import re
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, "..", "common")]
from check_docs import blocks, run  # noqa: E402  (the same block conventions)
from png_decode import read_png  # noqa: E402  (shared with tests/mpi/png_pixels_equal.py)

MINIMAL = re.compile(r"^renders:\s*\[\s*\{\s*field:\s*[A-Za-z0-9_-]+\s*\}\s*\]\s*$")
MIN_STDDEV, BRIGHT, DARK, MIN_SHARE = 10.0, 100, 60, 0.01


def luminances(path):
    width, height, bpp, rows = read_png(path)
    return [0.2126 * r[bpp * x] + 0.7152 * r[bpp * x + 1] + 0.0722 * r[bpp * x + 2] for r in rows for x in range(width)]


def picture_faults(path):
    """What makes the PNG at `path` flat, or [] when it is a picture."""
    y = luminances(path)
    n = len(y)
    mean = sum(y) / n
    sd = (sum((v - mean) ** 2 for v in y) / n) ** 0.5
    bright = sum(v > BRIGHT for v in y) / n
    dark = sum(v < DARK for v in y) / n
    print(f"      {os.path.basename(path)}: {n} pixels, luminance mean {mean:.1f} sd {sd:.1f}, "
          f"{100 * bright:.1f}% above {BRIGHT}, {100 * dark:.1f}% below {DARK}")
    faults = []
    if sd < MIN_STDDEV:
        faults.append(f"luminance sd {sd:.1f} < {MIN_STDDEV}")
    if bright < MIN_SHARE:
        faults.append(f"{100 * bright:.1f}% of pixels above {BRIGHT} (want {100 * MIN_SHARE:.0f}%)")
    if dark < MIN_SHARE:
        faults.append(f"{100 * dark:.1f}% of pixels below {DARK} (want {100 * MIN_SHARE:.0f}%)")
    return faults


def shim_bin(real_bin, folder):
    """build/bin/ of the scratch folder: the real programs, tessera-render at 96x96, 8 spp."""
    out = os.path.join(folder, "build", "bin")
    os.makedirs(out)
    for name in ("tessera-render", "tessera-synth"):
        extra = ' --width 96 --height 96 --spp 8' if name == "tessera-render" else ""
        path = os.path.join(out, name)
        open(path, "w").write(f'#!/bin/sh\nexec "{os.path.join(real_bin, name)}" "$@"{extra}\n')
        os.chmod(path, 0o755)
    return out


def main():
    repo, real_bin = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    md = os.path.join(repo, "docs", "config.md")
    runnable = [(line, lang, text) for line, lang, text, skipped in blocks(md)
                if not skipped and lang in ("yaml", "yml", "sh", "bash")]
    if not runnable:
        print("FAIL  docs/config.md has no runnable block")
        return 1
    line, lang, text = runnable[0]
    body = " ".join(l for l in text.splitlines() if l.strip() and not l.lstrip().startswith("#"))
    if lang not in ("yaml", "yml") or not MINIMAL.match(body):
        print(f"FAIL  docs/config.md:{line}: the first runnable block is not the smallest config "
              f"`renders: [{{field: NAME}}]` alone ({lang}: {body[:80]!r})")
        return 1
    print(f"ok    docs/config.md:{line}: the first runnable block is the smallest config: {body}")
    shells = [(l, t) for l, g, t in runnable[1:] if g in ("sh", "bash")]
    if not shells or "tessera-render" not in shells[0][1] or not any(MINIMAL.match(l.strip()) for l in shells[0][1].splitlines()):
        print("FAIL  docs/config.md: the first sh block after the smallest config does not render one "
              "(a line `renders: [{field: NAME}]` and tessera-render)")
        return 1
    line, script = shells[0]
    with tempfile.TemporaryDirectory(prefix="tessera_minimal_") as tmp:
        tmp = os.path.realpath(tmp)
        bindir = shim_bin(real_bin, tmp)
        env = dict(os.environ, PATH=bindir + os.pathsep + os.environ.get("PATH", ""))
        open(os.path.join(tmp, "block.sh"), "w").write(script)
        rc, out = run(["bash", "-eo", "pipefail", "block.sh"], tmp, env)
        if rc != 0:
            print(f"FAIL  docs/config.md:{line}: exit {rc}\n" + "".join("      > " + l + "\n" for l in out.splitlines()[-15:]))
            return 1
        pngs = sorted(glob.glob(os.path.join(tmp, "out", "**", "*.png"), recursive=True))
        if not pngs:
            print(f"FAIL  docs/config.md:{line}: wrote no PNG under out/")
            return 1
        faults = {p: picture_faults(p) for p in pngs}
    bad = {p: f for p, f in faults.items() if f}
    for p, f in bad.items():
        print(f"FAIL  docs/config.md:{line}: {os.path.basename(p)} is flat: " + "; ".join(f))
    if not bad:
        print(f"ok    docs/config.md:{line}: the smallest config renders a picture ({len(pngs)} PNG)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
