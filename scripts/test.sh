#!/usr/bin/env bash
# Sets everything up (packages, build) and runs the whole test suite with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
# The project venv first (.venv: pytest, numpy, nanobind, mpi4py, ...): the configure finds
# its nanobind and builds the Python package's module for the python-labelled tests.
bash scripts/python_env.sh >/dev/null
bash scripts/setup.sh
# MPI tests run several ranks on few cores, as root in containers.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
