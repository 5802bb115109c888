#!/usr/bin/env bash
# Performance benchmarks: run time against error, the thesis' tiling study, thread scaling,
# samples per second, targets (docs/BENCHMARKS.md). Benchmarks, not tests: nothing asserts a time.
#
#   bash bench/run_perf.sh [--quick] [--only data,error,thesis,scaling,targets,cache] [--no-plots]
#   (optional studies, not in the default run: --only cachebig (~30 min of callgrind on the
#   256x256 thesis renders), --only rescore (recompute the errors of the last error study))
#
# Builds tessera-render, tessera-synth and tessera-rmse in $TESSERA_PERF_BUILD (default
# build-perf, Release) if needed, generates the volumes (and fetches the head CT with
# scripts/fetch_ct.sh; skipped if unreachable), writes scenes, stats, CSV files, report.md and
# PNG plots into $TESSERA_PERF_RESULTS (default bench/results, git-ignored scratch).
# Plots need matplotlib, installed into bench/venv from PyPI on first use; without network the
# plots are skipped and everything else still runs.
# Full run: about 20-25 minutes on 2 cores (more on a shared machine); --quick: about 1 minute.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${TESSERA_PERF_BUILD:-build-perf}"
results="${TESSERA_PERF_RESULTS:-bench/results}"
args=()
plots=1
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) args+=(--quick) ;;
    --only) args+=(--only "$2"); shift ;;
    --only=*) args+=(--only "${1#--only=}") ;;
    --no-plots) plots=0 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) echo "run_perf: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

# Build (Release; tests off, they are not needed here)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DTESSERA_BUILD_TESTS=OFF >/dev/null
fi
cmake --build "$build" -j"$(nproc)" --target tessera-render tessera-synth tessera-rmse tessera-heat >/dev/null

# Measure
start=$(date +%s)
python3 bench/perf/perf.py --build "$build" --results "$results" "${args[@]}"
python3 bench/perf/report.py "$results" >/dev/null
echo "run_perf: $results/report.md ($(( $(date +%s) - start )) s of measurement)"

# Plots (optional)
if [ "$plots" = 1 ]; then
  if [ ! -x bench/venv/bin/python ] || ! bench/venv/bin/python -c 'import matplotlib, numpy' 2>/dev/null; then
    { python3 -m venv bench/venv && bench/venv/bin/pip install -q matplotlib numpy; } >/dev/null 2>&1 ||
      echo "run_perf: could not install matplotlib into bench/venv (no network?); plots skipped"
  fi
  if bench/venv/bin/python -c 'import matplotlib, numpy' 2>/dev/null; then
    bench/venv/bin/python bench/perf/plot.py "$results" | sed 's/^/run_perf: /'
  fi
fi
