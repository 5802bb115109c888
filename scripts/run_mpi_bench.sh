#!/usr/bin/env bash
# MPI tile rendering benchmark (bench/mpi_render_bench.cpp) for 1, 2 and 4 ranks; figures for
# docs/BENCHMARKS.md. Writes out/bench/mpi_render_bench.csv (per rank) and
# out/bench/mpi_render_bench_summary.csv (per rank count and mode), fresh each run.
#
#   scripts/run_mpi_bench.sh [extra mpi_render_bench flags...]     (BUILD_DIR, default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build}"
exe="$build/bench/mpi_render_bench"
if [ ! -x "$exe" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" -j"$(nproc)" --target mpi_render_bench
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p out/bench
rm -f out/bench/mpi_render_bench.csv out/bench/mpi_render_bench_summary.csv
# Ranks are not pinned, so that 1 thread per rank can use any free core.
for ranks in 1 2 4; do
  mpirun --oversubscribe --bind-to none -n "$ranks" "$exe" --csv out/bench/mpi_render_bench.csv "$@"
done
echo "run_mpi_bench: out/bench/mpi_render_bench.csv, out/bench/mpi_render_bench_summary.csv"
