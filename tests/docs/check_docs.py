#!/usr/bin/env python3
"""Checks that the examples in README.md and docs/*.md that claim to run do run.

    check_docs.py REPO_DIR BIN_DIR [FILE.md ...]

Convention (docs/cli.md, "Examples in the docs are tested"):
  * a ```yaml block is a complete scene: it is written to a scratch folder and checked with
    `tessera-render SCENE --check` (schema, output paths, volume size). Its volume file is made
    up (zeros of the right size); a block without `volume:` gets a small one appended, so that
    in situ configs are checked too;
  * a ```sh (or ```bash) block is run with `bash -eo pipefail` in a scratch folder holding a
    copy of configs/, with build/bin/ (and PATH) pointing at the programs; tessera-render is
    run at 48x32 pixels, 2 spp, so that commands on the demo scenes stay fast; Open MPI is
    allowed to run as root and to oversubscribe;
  * a ```python block is run as a script by the Python in TESSERA_DOCS_PYTHON (the project
    venv's, with the package built in build/python on PYTHONPATH; tests/docs/CMakeLists.txt
    sets both) in a scratch folder holding a copy of configs/, with matplotlib drawing off
    screen (MPLBACKEND=Agg); without TESSERA_DOCS_PYTHON it is skipped, saying so;
  * a block right after a line `<!-- fragment -->` (part of a config) or
    `<!-- not run: REASON -->` (a long command: the demo, the test suite, a build) is skipped.
Any other fence language (```cpp, ```c, plain ```) is not checked.
Prints one line per block; exits 1 if any block fails.
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

SKIP = re.compile(r"^\s*<!--\s*(fragment|not run\b.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)```\s*([A-Za-z0-9_+-]*)\s*$")
DTYPE_BYTES = {"uint8": 1, "int16": 2, "uint16": 2, "float32": 4, "float64": 8}
SMALL_VOLUME = "volume: {file: docs_check_volume.raw, dims: [8, 8, 8], dtype: float32}\n"


def blocks(path):
    """(line, language, text, skipped) for every fenced block of a Markdown file."""
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, lang = m.group(1), m.group(2).lower()
        j = i + 1
        while j < len(lines) and not re.match(r"^\s*```\s*$", lines[j]):
            j += 1
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        skipped = k >= 0 and SKIP.match(lines[k]) is not None
        body = "\n".join(l[len(indent):] if l.startswith(indent) else l for l in lines[i + 1:j])
        yield i + 1, lang, body + "\n", skipped
        i = j + 1


def make_volume(scene_text, folder):
    """Writes the raw file a scene's volume: block names (zeros), or appends a small volume."""
    if not re.search(r"^volume:", scene_text, re.M):
        open(os.path.join(folder, "docs_check_volume.raw"), "wb").write(b"\0" * 8 * 8 * 8 * 4)
        return scene_text.rstrip("\n") + "\n" + SMALL_VOLUME
    vol = scene_text[re.search(r"^volume:", scene_text, re.M).start():]
    vol = re.split(r"\n(?=\S)", vol, maxsplit=1)[0]  # up to the next top-level key
    file_m = re.search(r"\bfile:\s*([^\s,}]+)", vol)
    dims_m = re.search(r"\bdims:\s*\[\s*(\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*\]", vol)
    dtype_m = re.search(r"\bdtype:\s*([a-z0-9]+)", vol)
    header_m = re.search(r"\bheader_bytes:\s*(\d+)", vol)
    if file_m and dims_m and dtype_m and dtype_m.group(1) in DTYPE_BYTES:
        n = 1
        for d in dims_m.groups():
            n *= int(d)
        size = n * DTYPE_BYTES[dtype_m.group(1)] + (int(header_m.group(1)) if header_m else 0)
        target = os.path.normpath(os.path.join(folder, file_m.group(1).strip("'\"")))
        if target.startswith(folder + os.sep):
            os.makedirs(os.path.dirname(target), exist_ok=True)
            with open(target, "wb") as f:
                f.truncate(size)
    return scene_text


def shims(real_bin, folder):
    """build/bin/ of the scratch folder: small wrappers around the real programs."""
    out = os.path.join(folder, "build", "bin")
    os.makedirs(out)
    for name in os.listdir(real_bin):
        exe = os.path.join(real_bin, name)
        if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
            continue
        extra = ' --width 48 --height 32 --spp 2' if name == "tessera-render" else ""
        if name == "tessera-render":  # --help / --check / --version take no overrides
            script = ('#!/bin/sh\ncase " $* " in *" --help "*|*" -h "*|*" --version "*|*" --check "*) '
                      f'exec "{exe}" "$@";; esac\nexec "{exe}" "$@"{extra}\n')
        else:
            script = f'#!/bin/sh\nexec "{exe}" "$@"\n'
        path = os.path.join(out, name)
        open(path, "w").write(script)
        os.chmod(path, 0o755)
    return out


def run(cmd, cwd, env, timeout=120):
    try:
        p = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        return 124, f"timed out after {timeout} s"


def main():
    repo, real_bin = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    files = sys.argv[3:] or [os.path.join(repo, "README.md")] + sorted(glob.glob(os.path.join(repo, "docs", "*.md")))
    failures = checked = 0
    for md in files:
        rel = os.path.relpath(md, repo)
        for line, lang, text, skipped in blocks(md):
            if lang not in ("yaml", "yml", "sh", "bash", "shell", "python"):
                continue
            where = f"{rel}:{line}"
            if skipped:
                print(f"skip  {where} ({lang}, marked)")
                continue
            if lang == "python" and not os.environ.get("TESSERA_DOCS_PYTHON"):
                print(f"skip  {where} (python, TESSERA_DOCS_PYTHON not set: no Python package built)")
                continue
            checked += 1
            with tempfile.TemporaryDirectory(prefix="tessera_docs_") as tmp:
                tmp = os.path.realpath(tmp)
                bindir = shims(real_bin, tmp)
                env = dict(os.environ, PATH=bindir + os.pathsep + os.environ.get("PATH", ""),
                           OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                           OMPI_MCA_rmaps_base_oversubscribe="1")  # mpirun in containers
                if lang in ("yaml", "yml"):
                    scene = make_volume(text, tmp)
                    open(os.path.join(tmp, "scene.yaml"), "w").write(scene)
                    rc, out = run([os.path.join(bindir, "tessera-render"), "scene.yaml", "--check"], tmp, env)
                elif lang == "python":
                    shutil.copytree(os.path.join(repo, "configs"), os.path.join(tmp, "configs"))
                    open(os.path.join(tmp, "block.py"), "w").write(text)
                    rc, out = run([os.environ["TESSERA_DOCS_PYTHON"], "block.py"], tmp, dict(env, MPLBACKEND="Agg"))
                else:
                    shutil.copytree(os.path.join(repo, "configs"), os.path.join(tmp, "configs"))
                    open(os.path.join(tmp, "block.sh"), "w").write(text)
                    rc, out = run(["bash", "-eo", "pipefail", "block.sh"], tmp, env)
            if rc == 0:
                print(f"ok    {where} ({lang})")
            else:
                failures += 1
                hint = f" (scene.yaml line N is {rel} line {line}+N)" if lang in ("yaml", "yml") else ""
                print(f"FAIL  {where} ({lang}): exit {rc}{hint}\n" + "".join("      | " + l + "\n" for l in text.splitlines())
                      + "".join("      > " + l + "\n" for l in out.strip().splitlines()[-15:]))
    print(f"{checked} blocks checked, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
