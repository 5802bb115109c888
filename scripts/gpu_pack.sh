#!/usr/bin/env bash
# Packs prebuilt GPU binaries, their runtime libraries and the benchmark's data for a GPU
# machine that has nvcc, CMake, OpenMPI and Python but not Tessera's Debian libraries (this
# workplace's device machine: docs/gpu.md, "Tests on a GPU machine"), so that no device time
# goes to building. Run here, after building BUILD (a -DTESSERA_CUDA=ON build):
#
#   cmake --build build-gpu --target tessera_gpu_tests tessera_gpu_insitu_tests \
#     tessera_heat_cuda_tests tessera-heat tessera-render tessera-rmse lookup_cuda \
#     mesh_bench mesh_insitu_bench paged_field_bench
#   bash scripts/gpu_pack.sh [PACK]            # default PACK=build-gpu-pack (git-ignored)
#
# PACK then holds bin.tar.xz (the binaries, stripped, and the CTest files of BUILD's gpu
# tests), libs.tar.xz (TBB, OpenEXR, Imath, yaml-cpp, libpng, FreeType, Brotli: the shared
# libraries the binaries load that such a machine lacks; MPI is the machine's own, the same
# ABI as Debian's) and, when scripts/gpu_bench_data.sh has made it, data/ (the volumes and the
# CPU's references). Carry PACK to the machine and run scripts/gpu_remote.sh there. Settings:
# BUILD (default build-gpu), EXTRA_BUILDS (more build directories whose tessera-render and
# tessera_gpu_tests go along, e.g. kernel variants), DATA (default build-gpu-deps/data).
set -euo pipefail
cd "$(dirname "$0")/.."
pack=${1:-build-gpu-pack}
build=${BUILD:-build-gpu}
data=${DATA:-build-gpu-deps/data}
mkdir -p "$pack"
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
files=()
for f in tests/gpu/tessera_gpu_tests tests/gpu_insitu/tessera_gpu_insitu_tests tests/miniapp_gpu/tessera_heat_cuda_tests \
  bin/tessera-heat bin/tessera-render bench/perf/tessera-rmse bench/lookup/lookup_cuda bench/mesh_bench \
  bench/mesh_insitu_bench bench/paged_field_bench; do
  [[ -x $build/$f ]] && files+=("$build/$f") || echo "gpu_pack: no $build/$f (not built): left out"
done
for b in ${EXTRA_BUILDS:-}; do
  for f in bin/tessera-render tests/gpu/tessera_gpu_tests; do [[ -x $b/$f ]] && files+=("$b/$f"); done
done
for f in "${files[@]}"; do
  mkdir -p "$stage/$(dirname "$f")"
  strip -o "$stage/$f" "$f"
done
# CTest's files (the gpu label's tests run by ctest there) and what they read from BUILD
while IFS= read -r f; do
  mkdir -p "$stage/$(dirname "$f")" && cp "$f" "$stage/$f"
done < <(find "$build" -path '*/CMakeFiles' -prune -o \( -name CTestTestfile.cmake -o -name '*_include-*.cmake' \
  -o -name '*_tests-*.cmake' -o -name 'heat_gpu_distributed.yaml' \) -print)
tar cJf "$pack/bin.tar.xz" -C "$stage" .
libdir=/usr/lib/x86_64-linux-gnu
rm -rf "$stage/libs" && mkdir -p "$stage/libs"
for p in 'libtbb*.so.*' 'libOpenEXR-3_1.so.*' 'libIex-3_1.so.*' 'libIlmThread-3_1.so.*' 'libImath-3_1.so.*' \
  'libyaml-cpp.so.0.7*' 'libpng16.so.16*' 'libfreetype.so.6*' 'libbrotli*.so.1*'; do
  # shellcheck disable=SC2086  # the pattern is globbed on purpose
  cp -a $libdir/$p "$stage/libs/"
done
tar cJf "$pack/libs.tar.xz" -C "$stage/libs" .
[[ -d $data ]] && { rm -rf "$pack/data"; cp -r "$data" "$pack/data"; }
cp scripts/gpu_remote.sh "$pack/"
du -sh "$pack"/* | sed 's/^/gpu_pack: /'
echo "gpu_pack: carry $pack (64 MiB at most with the working tree on this workplace's device machine)"
