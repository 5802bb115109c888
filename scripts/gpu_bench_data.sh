#!/usr/bin/env bash
# Packs what the GPU benchmark (scripts/gpu_bench.sh, docs/BENCHMARKS.md "GPU against the CPU
# (issue 42)") needs besides the binaries, on a machine WITH network, for a GPU machine without
# it (and with a 64 MiB upload limit, binaries included):
#
#   1. the head CT and the brain MRI (scripts/fetch_ct.sh, scripts/fetch_mri.sh) and the heat
#      miniapp's 128^3 field, into DATA_DIR (ete.py --data; default bench/results/data);
#   2. those three volumes compressed with xz -9 into PACK_DIR (git-ignored; default
#      build-gpu-deps/data). xz, not zstd: a bare machine without the xz program still unpacks
#      it with Python's standard lzma module (gpu_bench.sh does), and it packs these volumes
#      smaller than zstd -19;
#   3. the CPU run's references (CPU_RESULTS/img/<case>/reference.exr and reference.json) into
#      PACK_DIR/ref/<case>/ and its CPU_RESULTS/ete.csv as PACK_DIR/ete_cpu.csv (default
#      CPU_RESULTS=bench/results/ete_cpu2), so that the GPU's renders are measured against the
#      same references and compared with the same CPU figures;
#   4. PACK_DIR/MANIFEST: each raw volume's sha256 and size (gpu_bench.sh checks them).
#
#   bash scripts/gpu_bench_data.sh [DATA_DIR] [PACK_DIR]
#   CPU_RESULTS=bench/results/ete_cpu2 BUILD=build bash scripts/gpu_bench_data.sh
#
# The heat field is made by ete.py's own recipe (BUILD/bin/tessera-heat, 400 steps; BUILD
# default build) unless DATA_DIR has it already, e.g. from the CPU run of ete.py --data
# DATA_DIR. Prints the packed sizes. Exit status: 0, or 1 when a volume could not be made.
set -euo pipefail
cd "$(dirname "$0")/.."
data=${1:-bench/results/data}
pack=${2:-build-gpu-deps/data}
cpu=${CPU_RESULTS:-bench/results/ete_cpu2}
refs=$cpu/img
build=${BUILD:-build}
mkdir -p "$data" "$pack"

# 1. The volumes (the fetch scripts do nothing when the checksummed file is there)
bash scripts/fetch_ct.sh "$data"
bash scripts/fetch_mri.sh "$data"
heat=heat_128x128x128_400steps_float32.raw  # perf_lib.DATASETS["heat"]["file"]
if [[ ! -f "$data/$heat" ]]; then
  echo "gpu_bench_data: making $data/$heat with $build/bin/tessera-heat (perf_lib.heat_volume)"
  python3 - "$build" "$data" <<'PY'
import os, sys
sys.path.insert(0, "bench/perf")
import perf_lib as P
b = P.Bench(os.getcwd(), os.path.abspath(sys.argv[1]), "/tmp/gpu_bench_data_results", quick=False)
b.data = os.path.abspath(sys.argv[2])
print(P.ensure_volume(b, "heat"))
PY
fi
for f in cranium.raw ch2better.raw "$heat"; do
  [[ -f "$data/$f" ]] || { echo "gpu_bench_data: $data/$f missing" >&2; exit 1; }
done

# 2. Compressed (xz -9; one thread, so the same bytes on every machine)
command -v xz > /dev/null || { echo "gpu_bench_data: xz not installed (apt-get install xz-utils)" >&2; exit 1; }
for f in cranium.raw ch2better.raw "$heat"; do
  out="$pack/$f.xz"
  if [[ ! -f "$out" || "$data/$f" -nt "$out" ]]; then
    xz -9 -T1 -c "$data/$f" > "$out.tmp" && mv "$out.tmp" "$out"
  fi
done

# 3. The CPU run's references, when it has run
if [[ -d "$refs" ]]; then
  for d in "$refs"/*/; do
    c=$(basename "$d")
    if [[ -f "$d/reference.exr" ]]; then
      mkdir -p "$pack/ref/$c"
      cp "$d/reference.exr" "$pack/ref/$c/"
      [[ -f "$d/reference.json" ]] && cp "$d/reference.json" "$pack/ref/$c/"
    fi
  done
  [[ -f $cpu/ete.csv ]] && cp "$cpu/ete.csv" "$pack/ete_cpu.csv"
else
  echo "gpu_bench_data: no CPU references in $refs yet (run bench/perf/ete.py --threads 2 first; see docs/BENCHMARKS.md)"
fi

# 4. The manifest: the raw volumes' sha256 (checked after unpacking) and the packed sizes
{
  for f in cranium.raw ch2better.raw "$heat"; do
    echo "raw $(sha256sum "$data/$f" | cut -d' ' -f1) $(stat -c %s "$data/$f") $f"
  done
} > "$pack/MANIFEST"
echo "gpu_bench_data: $pack (carry it to the GPU machine; scripts/gpu_bench.sh unpacks it):"
(cd "$pack" && find . -type f ! -name MANIFEST -printf '%s %p\n' | sort -k2 |
  awk '{printf "  %10.2f MiB  %s\n", $1 / 1048576, $2; t += $1} END {printf "  %10.2f MiB  in all\n", t / 1048576}')
