#!/usr/bin/env bash
# Distributed mode's sensitivity to the brick cache (docs/mpi.md, "Distributed mode"): at 4 ranks
# (oversubscribed on a small machine), 96^3, 256x256, 16 spp, brick shift 3/4/5 (8^3/16^3/32^3
# bricks) times cache fraction 0.2/0.4/0.6/1.0 of the global field, plus the replicated baseline.
# Writes bench/results/distributed_cache_sweep.csv.
#   bash scripts/run_distributed_cache_sweep.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
bin=build/bench/distributed_bench
[ -x "$bin" ] || cmake --build build -j2 --target distributed_bench
mkdir -p bench/results
csv=bench/results/distributed_cache_sweep.csv
rm -f "$csv"
common=(--grid 96 --image 256 256 --spp 16 --csv "$csv")
mpirun -n 4 --oversubscribe "$bin" --mode replicated "${common[@]}"
for shift in 3 4 5; do
  for frac in 0.2 0.4 0.6 1.0; do
    mpirun -n 4 --oversubscribe "$bin" --mode distributed --shift "$shift" --cache-fraction "$frac" "${common[@]}"
  done
done
echo "wrote $csv"
