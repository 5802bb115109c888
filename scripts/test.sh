#!/usr/bin/env bash
# Sets everything up (packages, build) and runs the whole test suite with CTest.
# Whatever ran before it (the demo command first, an older build/), it builds and runs every
# part it promises; a part that cannot run (no venv: the Python package's tests) makes it fail
# loudly at the end, after the rest has run, instead of passing a smaller suite.
set -euo pipefail
cd "$(dirname "$0")/.."
# The project venv first (.venv: pytest, numpy, nanobind, mpi4py, ...): the configure finds
# its nanobind and builds the Python package's module for the python-labelled tests
# (cmake/TesseraPython.cmake turns the module on in a build/ configured before the venv existed).
missing=()
venv_ok=1
bash scripts/python_env.sh >/dev/null || {
  venv_ok=0
  missing+=("the project venv (scripts/python_env.sh failed): the Python package and its tests, the denoising tests")
}
bash scripts/setup.sh
# MPI tests run several ranks on few cores, as root in containers.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# The project venv: pyoidn for the denoising tests, first on PATH so that Open Image Denoise is
# found as a user finds it.
if [ "$venv_ok" = 1 ]; then
  export PATH="$PWD/.venv/bin:$PATH"
  # The venv is there, so the Python suite must be: a build/ that left it out is a silent loss
  if ! ctest --test-dir build -N -L python | grep -q "Total Tests: [1-9]"; then
    missing+=("the Python package's tests (label python): the venv exists but build/ did not register them (TESSERA_BUILD_PYTHON is $(grep -m1 '^TESSERA_BUILD_PYTHON:' build/CMakeCache.txt | cut -d= -f2))")
  fi
fi
status=0
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@" || status=$?
if ((${#missing[@]})); then
  for m in "${missing[@]}"; do echo "test.sh: FAILED: could not run $m" >&2; done
  exit 1
fi
exit "$status"
