#!/usr/bin/env bash
# The heat miniapp demo: tessera-heat under mpirun with configs/heat.yaml; images land in
# out/heat/ (two views, every 10 steps as the render budget allows), and one MP4 per view when
# ffmpeg is installed. Each step does WORK_MS ms of extra computation (tessera-heat --work-ms),
# standing for a real simulation's step, so that the budget (a quarter of the simulation's
# time) pays for images.
# Builds tessera-heat first if it is missing.
#
#   scripts/run_heat_demo.sh [OUT_DIR] [extra tessera-heat flags...]
#   environment: RANKS (default 2), STEPS (default 100), GRID (default "64 64 64"),
#                WORK_MS (default 50), BUILD_DIR (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/heat}"
[ $# -gt 0 ] && shift
build="${BUILD_DIR:-build}"
exe="$build/bin/tessera-heat"
if [ ! -x "$exe" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" -j"$(nproc)" --target tessera-heat
fi
# Containers run as root; more ranks than cores is fine for a demo.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# shellcheck disable=SC2086  # GRID is three numbers
mpirun --oversubscribe -n "${RANKS:-2}" "$exe" --config configs/heat.yaml \
  --steps "${STEPS:-100}" --grid ${GRID:-64 64 64} --work-ms "${WORK_MS:-50}" --output-dir "$out" "$@"
echo "run_heat_demo: images in $out/"
# A short MP4 per view with Debian's ffmpeg when it is installed (apt-get install ffmpeg).
for view in heat_far heat_close; do
  if ! command -v ffmpeg >/dev/null; then echo "run_heat_demo: no MP4 (ffmpeg not installed)"; break; fi
  ls "$out/$view"_*.png >/dev/null 2>&1 || continue
  ffmpeg -loglevel error -y -framerate 4 -pattern_type glob -i "$out/${view}_*.png" \
    -vf "pad=ceil(iw/2)*2:ceil(ih/2)*2" -c:v libx264 -pix_fmt yuv420p "$out/$view.mp4" &&
    echo "run_heat_demo: wrote $out/$view.mp4"
done
