#!/usr/bin/env bash
# Builds the CUDA backend and runs the GPU tests (CTest label `gpu`) plus the estimator's
# consistency tests on the CPU, on a machine with a GPU, nvcc and CMake (docs/gpu.md). Meant to
# finish in well under 10 minutes: one build directory (build-gpu/), only what the tests need.
#
#   bash scripts/gpu_check.sh                # build-gpu/, architectures 90 (H100, H200)
#   TESSERA_CUDA_ARCHS="80;90" bash scripts/gpu_check.sh
#   TESSERA_GPU_BUILD=build-gpu-amr TESSERA_GPU_CMAKE_ARGS="-DTESSERA_CUDA_AMR=ON" bash scripts/gpu_check.sh
#
# TESSERA_GPU_CMAKE_ARGS: more CMake options, space-separated (a kernel under test:
# -DTESSERA_CUDA_AMR=ON, or a lane loop: -DTESSERA_CUDA_STEP_DEFER=ON; docs/gpu.md), best
# each in its own TESSERA_GPU_BUILD directory.
#
# A GPU machine may lack the Debian libraries Tessera links (TBB, OpenEXR, yaml-cpp, PNG,
# FreeType, glm, Catch2). Bring their files in a git-ignored folder, prepared on a Debian 12
# machine with network, and point the script at it with TESSERA_GPU_DEPS:
#
#   mkdir -p build-gpu-deps/debs && cd build-gpu-deps/debs
#   apt-get download libtbb-dev libtbb12 libtbbmalloc2 libopenexr-dev libopenexr-3-1-30 \
#     libimath-dev libimath-3-1-29 libyaml-cpp-dev libyaml-cpp0.7 libpng-dev libpng16-16 \
#     libfreetype-dev libfreetype6 libglm-dev catch2 zlib1g-dev libbrotli1 libdeflate0
#   cd .. && for d in debs/*.deb; do dpkg -x "$d" root; done
#   TESSERA_GPU_DEPS=$PWD/root bash ../scripts/gpu_check.sh
#
# (build-gpu-deps/ is ignored by git, as every /build-*/ is.) The script then passes
# CMAKE_PREFIX_PATH=$TESSERA_GPU_DEPS/usr and LD_LIBRARY_PATH=$TESSERA_GPU_DEPS/usr/lib/x86_64-linux-gnu,
# so the configure finds the packages' CMake files and the tests find the runtime libraries.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${TESSERA_GPU_BUILD:-build-gpu}
archs=${TESSERA_CUDA_ARCHS:-90}
cmake_args=(-DCMAKE_BUILD_TYPE=Release -DTESSERA_CUDA=ON "-DCMAKE_CUDA_ARCHITECTURES=$archs" -DTESSERA_WITH_MPI=OFF
  -DTESSERA_WITH_FORTRAN=OFF -DTESSERA_BUILD_PYTHON=OFF -DTESSERA_BUILD_BENCHMARKS=OFF -DTESSERA_CUDA_PTXAS_VERBOSE=ON)
# shellcheck disable=SC2206  # options are split on spaces on purpose
[[ -n "${TESSERA_GPU_CMAKE_ARGS:-}" ]] && cmake_args+=(${TESSERA_GPU_CMAKE_ARGS})
if [[ -n "${TESSERA_GPU_DEPS:-}" ]]; then
  deps=$(cd "$TESSERA_GPU_DEPS" && pwd)
  cmake_args+=("-DCMAKE_PREFIX_PATH=$deps/usr;$deps/usr/lib/x86_64-linux-gnu/cmake;$deps/usr/lib/cmake"
    "-DCMAKE_INCLUDE_PATH=$deps/usr/include" "-DCMAKE_LIBRARY_PATH=$deps/usr/lib/x86_64-linux-gnu")
  export LD_LIBRARY_PATH="$deps/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  export CPATH="$deps/usr/include${CPATH:+:$CPATH}"
fi
command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv || true
echo "gpu_check: configuring $build (CUDA architectures $archs)"
cmake -S . -B "$build" "${cmake_args[@]}"
jobs=$(nproc)
echo "gpu_check: building (kernel registers and spills below, -Xptxas -v)"
cmake --build "$build" -j"$jobs" --target tessera_gpu_tests tessera_tests 2>&1 |
  grep -E "ptxas info +: (Used|Compiling entry)|spill|error|Error|Built target" || true
# the build's status (the grep above hides it)
cmake --build "$build" -j"$jobs" --target tessera_gpu_tests tessera_tests > /dev/null
echo "gpu_check: the GPU tests"
ctest --test-dir "$build" -L gpu --output-on-failure
echo "gpu_check: the estimator's consistency tests on the CPU (the kernel the device shares)"
"$build/tests/tessera_tests" "[golden],[determinism],[furnace]"
