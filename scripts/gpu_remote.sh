#!/usr/bin/env bash
# On a GPU machine, from the repository root, with a pack of scripts/gpu_pack.sh carried there
# (no build, no network): the gpu label's tests, the adapter's GPU cases one at a time (a crash
# in one hides none of the others), the kernel variants' GPU tests, optionally
# the benchmark (scripts/gpu_bench.sh) and compute-sanitizer's memcheck.
#
#   bash scripts/gpu_remote.sh PACK OUT_DIR
#
# Settings: BUILD (default build-gpu, as packed), BENCH=1 (gpu_bench.sh into OUT_DIR/bench.tgz
# when PACK/data exists; its own settings pass through), MEMCHECK=0 (1: memcheck over the
# adapter's GPU tests and the core's memory, paged, background and mesh cases, last;
# MEMCHECK_LIMIT=90 seconds each; a wavefront variant's value tests too), WAVE_STEPS (with
# BENCH: the benchmark of a wavefront variant again at each of these steps per round),
# TESTS=1 (0: no tests, for a second run that benchmarks only), TEST_LIMIT=150
# (seconds for ctest). Logs in OUT_DIR (at most 8 files: what this workplace's machine sends
# back), progress on stdout.
set -uo pipefail
pack=${1:?usage: bash scripts/gpu_remote.sh PACK OUT_DIR}
out=${2:?usage: bash scripts/gpu_remote.sh PACK OUT_DIR}
build=${BUILD:-build-gpu}
mkdir -p "$out"
out=$(cd "$out" && pwd)
t0=$(date +%s)
say() { echo "[gpu_remote +$(($(date +%s) - t0))s] $*"; }
tar xJf "$pack/bin.tar.xz"
mkdir -p /tmp/tessera-libs && tar xJf "$pack/libs.tar.xz" -C /tmp/tessera-libs
export PATH=$PATH:/usr/local/cuda/bin
export LD_LIBRARY_PATH=/tmp/tessera-libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none
# The CTest files name the build machine's paths: its source tree, cmake, mpiexec and python
ctest_file=$build/CTestTestfile.cmake
src=$(sed -n 's/^# Source directory: //p' "$ctest_file")
[[ -n $src && ! -e $src ]] && mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src"
[[ -e $src/$build ]] || say "warning: $src/$build is not this tree's $build: ctest may not find its tests"
for tool in cmake mpiexec python3; do
  for want in $(grep -rhoE "\"(/[^\"]*/)?$tool\"" "$build" --include=CTestTestfile.cmake | tr -d '"' | sort -u); do
    [[ -e $want ]] || { mkdir -p "$(dirname "$want")" && ln -s "$(command -v $tool)" "$want"; }
  done
done
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$out/gpu.txt"
insitu=$build/tests/gpu_insitu/tessera_gpu_insitu_tests
if [[ ${TESTS:-1} == 1 ]]; then
  say "ctest -L gpu"
  timeout "${TEST_LIMIT:-150}" ctest --test-dir "$build" -L gpu --output-on-failure --timeout 120 > "$out/tests.log" 2>&1
  grep -E "tests passed|tests failed|\*\*\*|Passed|Failed" "$out/tests.log"
  say "the adapter's GPU cases, one at a time"
  "$insitu" --list-test-names-only 2>/dev/null | grep -v '^ *$' | while IFS= read -r c; do
    spec=$(printf '%s' "$c" | sed 's/\\/\\\\/g; s/,/\\,/g; s/\[/\\[/g; s/\]/\\]/g')
    timeout 120 "$insitu" "$spec" > /tmp/case.log 2>&1
    rc=$?
    echo "rc=$rc $c"
    ((rc)) && tail -25 /tmp/case.log
  done > "$out/insitu_cases.log" 2>&1
  grep -c "^rc=0" "$out/insitu_cases.log" | sed 's/^/  passed: /'
  grep "^rc=[1-9]" "$out/insitu_cases.log"
  for t in build-gpu-*/tests/gpu/tessera_gpu_tests; do
    [[ -x $t ]] || continue
    say "variant ${t%%/*}: its GPU tests"
    timeout 60 "$t" 2>&1 | tail -3
    [[ $t == *wave* ]] || continue  # the wavefront again with few slots (many lanes each), 1 step a round
    say "variant ${t%%/*}: its GPU tests, 1000 slots, 1 step a round"
    TESSERA_CUDA_WAVE_SLOTS=1000 TESSERA_CUDA_WAVE_STEPS=1 timeout 120 "$t" 2>&1 | tail -3
  done > "$out/variants.log" 2>&1
  cat "$out/variants.log"
fi
if [[ ${BENCH:-1} == 1 && -d $pack/data ]]; then
  say "gpu_bench.sh"
  rm -rf /tmp/tessera-bench && mkdir -p /tmp/tessera-bench
  BUILD=$build PACK=$pack/data bash scripts/gpu_bench.sh /tmp/tessera-bench/$build > "$out/bench.log" 2>&1
  grep "^|" "/tmp/tessera-bench/$build/ete_compare.md" 2>/dev/null
  # Kernel variants (EXTRA_BUILDS of gpu_pack.sh): the six cases at 256 spp each, same references
  for r in build-gpu-*/bin/tessera-render; do
    [[ -x $r ]] || continue
    v=${r%%/*}
    say "gpu_bench.sh, variant $v"
    BUILD=$v RMSE=$build/bench/perf/tessera-rmse LOOKUP=/nonexistent PACK=$pack/data GPU_SPP=256 MESH_LIMIT=0 \
      PAGED_LIMIT=0 MESH_CALL_LIMIT=0 TOTAL_LIMIT=60 bash scripts/gpu_bench.sh "/tmp/tessera-bench/$v" >> "$out/bench.log" 2>&1
    grep "^|" "/tmp/tessera-bench/$v/ete_compare.md" 2>/dev/null
    # The wavefront's steps per round (TESSERA_CUDA_WAVE_STEPS; WAVE_STEPS="1 2 8"): the same
    # image, another speed
    [[ $v == *wave* ]] || continue
    for st in ${WAVE_STEPS:-}; do
      say "gpu_bench.sh, variant $v, $st tracking steps a round"
      TESSERA_CUDA_WAVE_STEPS=$st BUILD=$v RMSE=$build/bench/perf/tessera-rmse LOOKUP=/nonexistent PACK=$pack/data \
        GPU_SPP=256 MESH_LIMIT=0 PAGED_LIMIT=0 MESH_CALL_LIMIT=0 TOTAL_LIMIT=60 \
        bash scripts/gpu_bench.sh "/tmp/tessera-bench/$v-steps$st" >> "$out/bench.log" 2>&1
      grep "^|" "/tmp/tessera-bench/$v-steps$st/ete_compare.md" 2>/dev/null
    done
  done
  tar czf "$out/bench.tgz" -C /tmp tessera-bench
fi
if [[ ${MEMCHECK:-0} == 1 ]] && command -v compute-sanitizer > /dev/null; then
  say "memcheck"
  { timeout "${MEMCHECK_LIMIT:-90}" compute-sanitizer --tool memcheck --leak-check no --print-limit 20 "$insitu" 2>&1 | tail -15
    timeout "${MEMCHECK_LIMIT:-90}" compute-sanitizer --tool memcheck --leak-check no --print-limit 20 "$build/tests/gpu/tessera_gpu_tests" \
      "[memory]~[sticky],[paged],GPU: the background*,GPU: a 1D*,GPU: a mesh in device memory*" 2>&1 | tail -15
    for t in build-gpu-*wave*/tests/gpu/tessera_gpu_tests; do  # the wavefront's queues and slots
      [[ -x $t ]] || continue
      echo "memcheck: ${t%%/*}"
      timeout "${MEMCHECK_LIMIT:-90}" compute-sanitizer --tool memcheck --leak-check no --print-limit 20 "$t" \
        "GPU against CPU: heat-like*,GPU: the same bits*,[values]~[mesh]" 2>&1 | tail -15
    done
  } > "$out/memcheck.log"
  cat "$out/memcheck.log"
fi
say "done"
