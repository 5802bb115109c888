#!/usr/bin/env bash
# The heat miniapp demo: tessera-heat under mpirun with configs/heat.yaml; images land in
# out/heat/ (two views, every 10 steps as the render budget allows), and one MP4 per view when
# ffmpeg is installed. Then the movie: the same simulation again with configs/heat_movie.yaml,
# a camera that turns 3.6 degrees a step, rendered every 2 steps into out/heat/movie/ and
# made into out/heat/heat_turn.mp4 (MOVIE=0 skips it; it adds about a minute of rendering on
# two cores). Each step of the first run does WORK_MS ms of extra computation (tessera-heat
# --work-ms), standing for a real simulation's step, so that the budget (a quarter of the
# simulation's time) pays for images.
# Then the refining run: tessera-heat --amr --levels 3 (refined boxes follow a heat source,
# their patches spread over the ranks) on 32^3 vertices for 40 steps with
# configs/heat_amr.yaml, images in OUT_DIR/amr/ (a few seconds; AMR=0 skips it).
# Builds tessera-heat first if it is missing.
#
#   scripts/run_heat_demo.sh [OUT_DIR] [extra tessera-heat flags...]
#   environment: RANKS (default 2), STEPS (default 100), GRID (default "64 64 64"),
#                WORK_MS (default 50), BUILD_DIR (default build), MOVIE (default 1), AMR (default 1)
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
# Refinement levels (docs/miniapp.md): three levels, ratio 2, around the first heat source
if [ "${AMR:-1}" != 0 ]; then
  mpirun --oversubscribe -n "${RANKS:-2}" "$exe" --config configs/heat_amr.yaml --amr --levels 3 \
    --steps 40 --grid 32 32 32 --output-dir "$out/amr" "$@"
  echo "run_heat_demo: refinement-level images in $out/amr/"
fi
# The turning camera (configs/heat_movie.yaml): no extra work per step and no render budget,
# so that every second step renders and the movie has all its frames.
if [ "${MOVIE:-1}" != 0 ]; then
  # shellcheck disable=SC2086  # GRID is three numbers
  mpirun --oversubscribe -n "${RANKS:-2}" "$exe" --config configs/heat_movie.yaml \
    --steps "${STEPS:-100}" --grid ${GRID:-64 64 64} --output-dir "$out/movie" "$@"
  echo "run_heat_demo: movie frames in $out/movie/"
fi
# A short MP4 per view with Debian's ffmpeg when it is installed (apt-get install ffmpeg):
# the two fixed views at 4 frames a second, the turning one at 12. Without ffmpeg, one line
# says so and the demo goes on (the PNGs are there).
movie() {  # movie VIEW FOLDER FRAMERATE
  ls "$2/$1"_*.png >/dev/null 2>&1 || return 0
  if ffmpeg -loglevel error -y -framerate "$3" -pattern_type glob -i "$2/${1}_*.png" \
    -vf "pad=ceil(iw/2)*2:ceil(ih/2)*2" -c:v libx264 -pix_fmt yuv420p "$out/$1.mp4"; then
    echo "run_heat_demo: wrote $out/$1.mp4"
  else
    echo "run_heat_demo: ffmpeg could not make $out/$1.mp4"
  fi
}
if ! command -v ffmpeg >/dev/null; then
  echo "run_heat_demo: no MP4 (ffmpeg not installed)"
else
  movie heat_far "$out" 4
  movie heat_close "$out" 4
  movie heat_turn "$out/movie" 12
fi
