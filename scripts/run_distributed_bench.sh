#!/usr/bin/env bash
# Replicated against distributed mode (docs/mpi.md, "Distributed mode"; docs/BENCHMARKS.md):
# for 1, 2, 4 and 8 ranks (oversubscribed on a small machine) and the grids given, one process
# per mode so that peak memory is the mode's own. Writes bench/results/distributed_bench.csv.
#   bash scripts/run_distributed_bench.sh [grid ...]       (default: 64 128)
set -euo pipefail
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
bin=build/bench/distributed_bench
[ -x "$bin" ] || cmake --build build -j2 --target distributed_bench
mkdir -p bench/results
csv=bench/results/distributed_bench.csv
grids=("$@")
[ ${#grids[@]} -gt 0 ] || grids=(64 128)
for grid in "${grids[@]}"; do
  for np in 1 2 4 8; do
    for mode in replicated distributed; do
      [ "$np" = 1 ] && [ "$mode" = distributed ] && continue  # one rank is always replicated
      for scat in "" --multiple; do
        mpirun -n "$np" --oversubscribe "$bin" --mode "$mode" --grid "$grid" --csv "$csv" $scat
      done
    done
  done
done
echo "wrote $csv"
