#!/usr/bin/env bash
# Creates (or brings up to date) the project's Python environment in .venv from PyPI:
# the packages in scripts/requirements.txt (pytest, numpy, mpi4py, pyoidn, the Python
# package's build tools). Safe to run again: it reinstalls only when requirements.txt changes.
# Prints the venv's python on stdout's last line.
set -euo pipefail
cd "$(dirname "$0")/.."
# venv support, and Python.h for the Python package's extension module (TESSERA_BUILD_PYTHON)
has_headers='import os, sys, sysconfig; sys.exit(not os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h")))'
if ! python3 -c 'import ensurepip' 2>/dev/null || ! python3 -c "$has_headers"; then
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends python3-venv python3-dev
fi
[ -x .venv/bin/python ] || python3 -m venv .venv
want="$(sha256sum scripts/requirements.txt | cut -d' ' -f1)"
if [ "$(cat .venv/.requirements.sha256 2>/dev/null)" != "$want" ]; then
  .venv/bin/pip install -q --upgrade pip >/dev/null
  .venv/bin/pip install -q -r scripts/requirements.txt
  echo "$want" > .venv/.requirements.sha256
fi
echo "$PWD/.venv/bin/python"
