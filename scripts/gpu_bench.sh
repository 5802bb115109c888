#!/usr/bin/env bash
# The GPU side of issue 42's benchmark (docs/BENCHMARKS.md, "GPU against the CPU (issue 42)"),
# run ON the GPU machine from the repository root, with prebuilt binaries and the packed data:
#
#   LD_LIBRARY_PATH=... bash scripts/gpu_bench.sh OUT_DIR
#
# Needs (carried from the build machine; nothing is built or fetched here):
#   $BUILD/bin/tessera-render (BUILD, default build-gpu: a -DTESSERA_CUDA=ON build), and
#   RMSE (default $BUILD/bench/perf/tessera-rmse; a CPU tool: build/'s does) and LOOKUP
#       (default $BUILD/bench/lookup/lookup_cuda; cudart linked statically, so any CUDA
#       build's, e.g. build-gpu-c/'s); the caller's LD_LIBRARY_PATH finds their libraries,
#       e.g. build-gpu-deps/root/usr/lib/x86_64-linux-gnu
#   $PACK (default build-gpu-deps/data), from scripts/gpu_bench_data.sh: the compressed
#       volumes, MANIFEST, the CPU run's references ref/<case>/ and its ete_cpu.csv
# Writes into OUT_DIR: gpu.txt (nvidia-smi), lookup_cuda.{txt,csv}, mesh_bench.{txt,csv},
# mesh_insitu_bench.{txt,csv} (the device's) and mesh_insitu_bench_cpu.{txt,csv},
# paged_field_bench.{txt,csv},
# ete_gpu_spp<N>/ete.{csv,md}
# and stats/, the GPU's run0.exr per case, ete_compare.md (against the CPU's CSV), resources.txt
# (the kernels' registers and spills, when cuobjdump is on PATH), timing.txt. Progress lines on
# stdout. Meant to finish in well under 4 minutes on one H100/H200: every step has a time limit
# (a step that runs out is reported and the next one runs).
#
# Settings (environment):
#   GPU_SPP="256 64"   the GPU's spp, one ete.py pass per value, in order (the CPU took 64: at
#                      64 the plain time ratio is the speedup at equal error; at 256 the
#                      efficiency ratio, with less of the per-render fixed cost)
#   REPS=3 WARMUP=1 THREADS=2 ONLY=<cases, comma-separated; default all six>
#   DEVICE=cuda        (cpu: the same steps on the CPU, to check the script where there is no GPU)
#   FIELD_DTYPE=native the GPU renders the int16 CT and uint8 MRI in their own dtypes, as the
#                      CPU does (every table in docs/BENCHMARKS.md); float32: widened float32
#                      copies (the same values), to compare the integer kernels with the float one
#   MESH_LIMIT=30      seconds for bench/mesh_bench on the device (0: skipped), before the cases
#   PAGED_LIMIT=30     seconds for bench/paged_field_bench on the device (0: skipped), likewise
#   MESH_CALL_LIMIT=40 seconds for each of bench/mesh_insitu_bench's two runs (the adapter's call
#                      over a 96^3 hex mesh: moved, same, promised; on the device, then on the
#                      CPU with THREADS; 0: skipped)
#   NCU=0              1: Nsight Compute on one kernel launch of each NCU_CASES case
#                      (default ct_single,ct_multiple) after the benchmark, NCU_LIMIT=120 s each
#   CASE_LIMIT=60 LOOKUP_LIMIT=60 TOTAL_LIMIT=200 (seconds: a case, the lookup ceiling, and
#                      the whole script: the cases left when it runs out are skipped), WORK=/tmp/tessera-gpu-bench (the unpacked data,
#                      the float32 copies, all images: not under OUT_DIR, which travels back)
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: bash scripts/gpu_bench.sh OUT_DIR}
mkdir -p "$out"
out=$(cd "$out" && pwd)
build=${BUILD:-build-gpu}
rmse=${RMSE:-$build/bench/perf/tessera-rmse}
lookup=${LOOKUP:-$build/bench/lookup/lookup_cuda}
pack=${PACK:-build-gpu-deps/data}
work=${WORK:-/tmp/tessera-gpu-bench}
gpu_spp=${GPU_SPP:-256 64}
reps=${REPS:-3}
warmup=${WARMUP:-1}
threads=${THREADS:-2}
device=${DEVICE:-cuda}
field_dtype=${FIELD_DTYPE:-native}
case_limit=${CASE_LIMIT:-60}
lookup_limit=${LOOKUP_LIMIT:-60}
mesh_limit=${MESH_LIMIT:-30}
paged_limit=${PAGED_LIMIT:-30}
mesh_call_limit=${MESH_CALL_LIMIT:-40}
total_limit=${TOTAL_LIMIT:-200}
cases=${ONLY:-ct_single,mri_single,heat_single,ct_multiple,mri_multiple,heat_multiple}
export PYTHONUNBUFFERED=1
t_begin=$(date +%s)
say() { echo "[gpu_bench $(date +%H:%M:%S) +$(($(date +%s) - t_begin))s] $*"; }
mark() { echo "$1 $(($(date +%s) - t_begin))" >> "$out/timing.txt"; }
: > "$out/timing.txt"

for exe in "$build/bin/tessera-render" "$rmse"; do
  [[ -x $exe ]] || { say "missing $exe (build it: cmake --build $build --target tessera-render tessera-rmse)"; exit 1; }
done
[[ -f $pack/MANIFEST ]] || { say "missing $pack/MANIFEST (scripts/gpu_bench_data.sh packs it)"; exit 1; }
{ nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv 2>&1
  nproc; uptime; } > "$out/gpu.txt"
say "$(head -2 "$out/gpu.txt" | tail -1)"

# 1. The volumes, unpacked and checked against the manifest
mkdir -p "$work/data"
while read -r kind sha size name; do
  [[ $kind == raw ]] || continue
  dst="$work/data/$name"
  if [[ ! -f $dst ]] || [[ $(stat -c %s "$dst") != "$size" ]]; then
    [[ -f $pack/$name.xz ]] || { say "no $pack/$name.xz"; exit 1; }
    if command -v xz > /dev/null; then xz -d -c "$pack/$name.xz" > "$dst"
    else python3 -c "import lzma, shutil, sys; shutil.copyfileobj(lzma.open(sys.argv[1]), open(sys.argv[2], 'wb'), 1 << 24)" \
      "$pack/$name.xz" "$dst"; fi
  fi
  [[ $(sha256sum "$dst" | cut -d' ' -f1) == "$sha" ]] || { say "$dst: sha256 differs from $pack/MANIFEST"; exit 1; }
done < "$pack/MANIFEST"
say "data unpacked into $work/data"
mark unpacked

# 2. The bare lookup loop's ceiling on the GPU
if [[ -x $lookup ]]; then
  say "lookup_cuda (limit ${lookup_limit} s)"
  timeout "$lookup_limit" "$lookup" --sizes 128,256 --reps 5 \
    --raw "$work/data/cranium.raw" 256 256 108 int16 --csv "$out/lookup_cuda.csv" 2>&1 | tee "$out/lookup_cuda.txt"
  say "lookup_cuda: exit ${PIPESTATUS[0]}"
else
  say "no $lookup: the lookup ceiling skipped"
fi
mark lookup

# 3. The render kernels' registers and spills (compile-time figures; cuobjdump is in the toolkit)
if command -v cuobjdump > /dev/null; then
  for f in "$build/bin/tessera-render" "$build"/core/libtessera_core.* "$lookup"; do
    [[ -f $f ]] && { echo "== $f"; cuobjdump -res-usage "$f" 2>&1 | grep -E "Function|REG" ; }
  done > "$out/resources.txt" 2>&1
  say "registers and spills: resources.txt"
fi

# bench/NAME on the device for at most LIMIT seconds, its table and CSV as OUT_DIR/NAME.{txt,csv};
# nothing when the build has no such program or LIMIT is 0
device_bench() {
  local name=$1 limit=$2 bin=$build/bench/$1
  [[ -x $bin ]] && ((limit > 0)) || return 0
  say "$name --device $device (limit ${limit} s)"
  timeout "$limit" "$bin" --device "$device" --threads "$threads" --reps 2 --csv "$out/$name.csv" 2>&1 |
    tee "$out/$name.txt"
  say "$name: exit ${PIPESTATUS[0]}"
}

# 3b. Curvilinear and unstructured meshes on the GPU (bench/mesh_bench: grid, hex mesh, tet
# mesh; the CPU's figures are docs/BENCHMARKS.md's)
device_bench mesh_bench "$mesh_limit"
mark mesh
# The adapter's call over a mesh whose values change (seconds per call and the bytes copied to
# the device: an unchanged mesh's geometry and tables stay there), on the device and the CPU
mesh_call() {
  local tag=$1 dev=$2 bin=$build/bench/mesh_insitu_bench
  [[ -x $bin ]] && ((mesh_call_limit > 0)) || return 0
  say "mesh_insitu_bench --device $dev (limit ${mesh_call_limit} s)"
  timeout "$mesh_call_limit" "$bin" --device "$dev" --threads "$threads" --cells 96 --steps 6 \
    --csv "$out/$tag.csv" 2>&1 | tee "$out/$tag.txt"
  say "$tag: exit ${PIPESTATUS[0]}"
}
mesh_call mesh_insitu_bench "$device"
mesh_call mesh_insitu_bench_cpu cpu
mark mesh_call

# 3c. A distributed (paged) field on the GPU (bench/paged_field_bench: whole field, every brick
# resident, a pool of 1/8 of the bricks with replayed launches; docs/gpu.md, "Distributed
# fields on the GPU")
device_bench paged_field_bench "$paged_limit"
mark paged

# 4. Time to equal error: the six cases on the GPU against the CPU's references, per spp
args=(--build "$build" --rmse "$rmse" --data "$work/data" --reference-dir "$pack/ref" --device "$device" --threads "$threads"
  --reps "$reps" --warmup "$warmup" --field-dtype "$field_dtype")
csvs=()
for spp in $gpu_spp; do
  res="$work/ete_gpu_spp$spp"
  dst="$out/ete_gpu_spp$spp"
  mkdir -p "$dst"
  rows=()
  for c in ${cases//,/ }; do
    left=$((total_limit - ($(date +%s) - t_begin)))
    if ((left < 5)); then
      say "$c at $spp spp skipped: TOTAL_LIMIT ${total_limit} s reached"
      continue
    fi
    limit=$((left < case_limit ? left : case_limit))
    say "ete.py $c, $spp spp (limit $limit s)"
    timeout "$limit" python3 bench/perf/ete.py "${args[@]}" --spp "$spp" --only "$c" --results "$res/$c" \
      --label "gpu_spp$spp" 2>&1 | grep -v "^tessera: " | grep -E "^\[perf|ete.py|Error|error" || true
    [[ -f $res/$c/ete.csv ]] && rows+=("$res/$c/ete.csv") || say "$c at $spp spp: no result (failed or over $limit s)"
    mkdir -p "$dst/stats" "$dst/img"
    cp "$res/$c"/stats/*.json "$dst/stats/" 2>/dev/null
    cp "$res/$c"/scenes/*.yaml "$dst/stats/" 2>/dev/null
    [[ -f $res/$c/img/$c/run0.exr ]] && cp "$res/$c/img/$c/run0.exr" "$dst/img/$c.exr"
    mark "ete_${c}_spp$spp"
  done
  # One CSV for the pass: the header once
  if ((${#rows[@]})); then
    { head -1 "${rows[0]}"; for r in "${rows[@]}"; do tail -n +2 "$r"; done; } > "$dst/ete.csv"
    csvs+=("$dst/ete.csv")
  fi
done

# 5. Against the CPU
if [[ -f $pack/ete_cpu.csv ]] && ((${#csvs[@]})); then
  python3 bench/perf/ete_compare.py "$pack/ete_cpu.csv" "${csvs[@]}" --out "$out/ete_compare.md" \
    --cpu-name "the 2-core development VM"
fi
mark compare

# 6. Nsight Compute on one launch of each NCU_CASES case (NCU=1 and ncu on PATH): threads active
# per warp instruction, occupancy, registers (ncu_<case>.csv), then, in a run of its own so that
# a metric this ncu lacks costs only that file, the warps' stall reasons per issued
# instruction (instruction fetch: "no_instruction"; ncu_<case>_stalls.csv); NCU_LIMIT seconds
# each
if [[ ${NCU:-0} == 1 ]] && command -v ncu > /dev/null; then
  ncu_cases=${NCU_CASES:-ct_single,ct_multiple}
  for c in ${ncu_cases//,/ }; do
    c=${c//[^a-z_]/}
    scene=$(ls "$work/ete_gpu_spp256/$c"/scenes/*.yaml 2>/dev/null | head -1)
    [[ -n $scene ]] || { say "ncu $c: no 256 spp scene (the case did not run)"; continue; }
    say "ncu $c (limit ${NCU_LIMIT:-120} s)"
    timeout "${NCU_LIMIT:-120}" ncu --kernel-name regex:pixel_samples --launch-count 1 --csv --page details \
      --section SpeedOfLight --section Occupancy --section LaunchStats --section WarpStateStats \
      --section SchedulerStats --metrics smsp__thread_inst_executed_per_inst_executed.ratio \
      "$build/bin/tessera-render" "$scene" --render run0 --quiet > "$out/ncu_$c.csv" 2> "$out/ncu_$c.err"
    say "ncu $c: exit $?"
    timeout "${NCU_LIMIT:-120}" ncu --kernel-name regex:pixel_samples --launch-count 1 --csv --page raw \
      --metrics 'regex:^smsp__average_warps_issue_stalled_.*_per_issue_active\.ratio$' \
      "$build/bin/tessera-render" "$scene" --render run0 --quiet > "$out/ncu_${c}_stalls.csv" 2>> "$out/ncu_$c.err"
    say "ncu $c, stall reasons: exit $?"
  done
fi
mark done
say "done in $(($(date +%s) - t_begin)) s; results in $out"
