#!/usr/bin/env bash
# Builds the project and all its tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (gcc, RelWithDebInfo, frame pointers kept, any UB report fatal) into ./build-asan and runs
# them with CTest: first everything but the MPI tests and the docs examples (label "docs", run by
# scripts/test.sh), then the MPI tests (label "mpi") with
# Open MPI's own never-freed allocations suppressed (scripts/lsan_openmpi.supp).
#   TESSERA_SANITIZE_MPI=0   skip the MPI tests
#   extra arguments          go to both ctest runs (e.g. -R furnace)
set -euo pipefail
cd "$(dirname "$0")/.."

TESSERA_SETUP_SKIP_BUILD=1 bash scripts/setup.sh

flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
mkdir -p build-asan
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DTESSERA_BUILD_BENCHMARKS=OFF -DTESSERA_BUILD_PYTHON=OFF -DTESSERA_CUDA=OFF ${TESSERA_CMAKE_ARGS:-} > build-asan/configure.log 2>&1 \
  || { cat build-asan/configure.log; exit 1; }
cmake --build build-asan -j"$(nproc)"

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:check_initialization_order=1:strict_init_order=1"
# The docs examples (label docs) run mpirun and the programs as a user would: checked by the
# main test run; under ASan their Open MPI allocations would need the MPI pass's suppressions.
ctest --test-dir build-asan --output-on-failure -j"$(nproc)" --timeout 1500 -LE "mpi|docs" "$@"

if [ "${TESSERA_SANITIZE_MPI:-1}" = 1 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  export OMPI_MCA_mca_base_component_disable_dlclose=1  # keep component names in leak stacks
  export ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"
  export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan_openmpi.supp:print_suppressions=0"
  ctest --test-dir build-asan --output-on-failure -j"$(nproc)" -L mpi "$@"
fi
