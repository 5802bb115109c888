#!/usr/bin/env bash
# Sets everything up, then renders the demos into out/:
#  1. tessera-render on a synthetic volume it generates (no download): out/demo/
#  2. the heat-equation miniapp under mpirun, rendering in situ every few steps: out/heat/
set -euo pipefail
cd "$(dirname "$0")/.."
# Builds only the programs the demo runs (build/bin/), not the tests and benchmarks; adds
# ffmpeg for the heat demo's MP4s.
TESSERA_SETUP_DEMO=1 TESSERA_SETUP_TARGETS="tessera-render tessera-synth tessera-heat" bash scripts/setup.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

mkdir -p data out
[ -f data/blobs.raw ] || ./build/bin/tessera-synth data/blobs.raw --dims 128 128 128 --kind blobs
./build/bin/tessera-render configs/demo.yaml --stats out/demo/stats.json
# The multiple-scattering image again, denoised (--denoise = image.denoise: true) with Open
# Image Denoise from the project venv (scripts/python_env.sh installs pyoidn from PyPI);
# skipped when that cannot be had (no network): the images above do not need it.
if bash scripts/python_env.sh > /dev/null 2>&1 &&
   PATH="$PWD/.venv/bin:$PATH" ./build/bin/tessera-render configs/demo.yaml --render blobs_multiple \
     --denoise -o out/demo/blobs_multiple_denoised.png; then :
else
  echo "demo: no denoised image (Open Image Denoise not found: python3 -m pip install pyoidn)"
fi
echo "demo: wrote $(ls out/demo/*.png | tr '\n' ' ')"

# The heat miniapp under mpirun (RANKS, STEPS, GRID: see scripts/run_heat_demo.sh).
bash scripts/run_heat_demo.sh out/heat
