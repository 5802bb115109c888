#!/usr/bin/env bash
# Fuzzes the YAML config loader, the raw volume loader and the envmap (EXR) reader (fuzz/,
# libFuzzer) for a short fixed time each. Builds them with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer into ./build-fuzz (installing clang first if missing:
# scripts/setup.sh with TESSERA_SETUP_FUZZ=1).
#   FUZZ_SECONDS   time per target (default 30)
#   FUZZ_JOBS      parallel build jobs (default nproc)
# Seed corpus: configs/*.yaml for the config parser; a few generated volumes for the raw
# loader; small EXRs in every scanline compression and tiled, written by fuzz_envmap itself
# (TESSERA_FUZZ_WRITE_SEEDS) for the envmap reader. The growing corpus is kept in
# build-fuzz/corpus/ between runs; a finding (crash, sanitizer report, contract violation)
# stops the script with a non-zero status and leaves
# the input in build-fuzz/findings/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${FUZZ_SECONDS:-30}"

TESSERA_SETUP_FUZZ=1 TESSERA_SETUP_SKIP_BUILD=1 bash scripts/setup.sh

san="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
mkdir -p build-fuzz
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_FLAGS="$san" -DCMAKE_CXX_FLAGS="$san" \
  -DTESSERA_BUILD_FUZZERS=ON -DTESSERA_BUILD_TESTS=OFF -DTESSERA_BUILD_APPS=OFF \
  -DTESSERA_BUILD_BENCHMARKS=OFF -DTESSERA_WITH_MPI=OFF -DTESSERA_BUILD_PYTHON=OFF -DTESSERA_CUDA=OFF > build-fuzz/configure.log 2>&1 \
  || { cat build-fuzz/configure.log; exit 1; }
cmake --build build-fuzz -j"${FUZZ_JOBS:-$(nproc)}" --target fuzz_parse_config fuzz_raw_volume fuzz_envmap

# Seed corpora
mkdir -p build-fuzz/corpus/parse_config build-fuzz/corpus/raw_volume build-fuzz/corpus/envmap \
  build-fuzz/findings
cp configs/*.yaml build-fuzz/corpus/parse_config/
hex2bin() { local h="$1" i; for ((i = 0; i < ${#h}; i += 2)); do printf "\\x${h:i:2}"; done; }
seed() {  # seed NAME HEADER_HEX PAYLOAD_HEX: a 34-byte header (fuzz/fuzz_raw_volume.cpp) + data
  hex2bin "$2$3" > "build-fuzz/corpus/raw_volume/$1"
}
zeros() { printf '%0*d' "$1" 0; }
small() {  # small DTYPE FLAGS D0-1 D1-1 D2-1 HEADER_BYTES (hex bytes): the header with small dims
  printf '%s%s%s%s%s%s%s%s' "$1" "$2" "$3" "$4" "$5" "$(zeros 42)" "$6" "$(zeros 14)"
}
i64() { printf '%02x00000000000000' "$1"; }
seed f32_2x2x2 "$(small 03 02 01 01 01 00)" "$(printf '0000803f%.0s' {1..8})"   # float32 ones
seed u8_4x1x1_big "$(small 00 03 03 00 00 03)" "aabbcc00408020"                 # 3 header bytes
seed f64_nan_inf "$(small 04 02 01 00 00 00)" "000000000000f87f000000000000f07f" # NaN, +Inf
seed u16_int64_dims "0200$(i64 1)$(i64 2)$(i64 1)$(i64 0)" "34127856"              # dims as int64
TESSERA_FUZZ_WRITE_SEEDS=build-fuzz/corpus/envmap ./build-fuzz/fuzz/fuzz_envmap -runs=0 \
  > build-fuzz/envmap_seeds.log 2>&1 || { cat build-fuzz/envmap_seeds.log; exit 1; }

ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export ASAN_OPTIONS UBSAN_OPTIONS
status=0
for target in parse_config raw_volume envmap; do
  echo "fuzz: $target for ${seconds}s"
  ./build-fuzz/fuzz/fuzz_$target -max_total_time="$seconds" -max_len=8192 -timeout=20 \
    -print_final_stats=1 -artifact_prefix="build-fuzz/findings/${target}-" \
    "build-fuzz/corpus/$target" 2>&1 | tail -n 25 || status=1
done
if [ "$status" -ne 0 ]; then
  echo "fuzz: FINDINGS in build-fuzz/findings/:"; ls -l build-fuzz/findings/
  exit 1
fi
echo "fuzz: no findings"
