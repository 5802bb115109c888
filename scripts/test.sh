#!/usr/bin/env bash
# Sets everything up (packages, build) and runs the whole test suite with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
# The project venv first (.venv: pytest, numpy, nanobind, mpi4py, ...): the configure finds
# its nanobind and builds the Python package's module for the python-labelled tests.
# Without it (no network, say) the build and the C++/Fortran tests still run.
bash scripts/python_env.sh >/dev/null || echo "test.sh: no project venv: the Python package is not built" >&2
bash scripts/setup.sh
# MPI tests run several ranks on few cores, as root in containers.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# The project venv (scripts/python_env.sh): pyoidn for the denoising tests, first on PATH so
# that Open Image Denoise is found as a user finds it; without it those tests report SKIPPED.
if bash scripts/python_env.sh > /dev/null; then
  export PATH="$PWD/.venv/bin:$PATH"
else
  echo "test.sh: scripts/python_env.sh failed: the tests that need its packages are skipped" >&2
fi
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
