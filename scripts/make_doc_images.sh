#!/usr/bin/env bash
# The pictures of docs/config.md, each made from a config under docs/images/ that says how:
#   "distance: fit"   docs/images/distance_fit_{wide,square,tall}.png   (distance_fit.yaml)
#   "Moving cameras"  docs/images/moving_turn_NNNN.png, a turning orbit, and
#                     docs/images/moving_fly_NNNN.png, a keyframed fly-in (moving_cameras.yaml)
# Both render a linear ramp that tessera-synth writes to /tmp/ramp.raw. Builds tessera-synth
# and tessera-render first when they are missing. Takes a few seconds.
#
#   scripts/make_doc_images.sh          environment: BUILD_DIR (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build}"
for exe in tessera-synth tessera-render; do
  if [ ! -x "$build/bin/$exe" ]; then
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
    cmake --build "$build" -j"$(nproc)" --target "$exe"
  fi
done
"$build/bin/tessera-synth" /tmp/ramp.raw --dims 32 32 32 --kind linear
"$build/bin/tessera-render" docs/images/distance_fit.yaml -o docs/images/distance_fit --quiet
# Annotations: a title, a text line and a colour bar on synthetic blobs (annotations.yaml)
"$build/bin/tessera-synth" /tmp/blobs.raw --dims 64 64 64 --kind blobs
"$build/bin/tessera-render" docs/images/annotations.yaml --step 120 -o docs/images/annotations.png --quiet
# Moving cameras: the orbit at azimuth 0, 45, 90 and 135 (1.5 degrees a step); the keyframes
# at steps 0, 30 and 60, and halfway between them
for n in 0 30 60 90; do
  "$build/bin/tessera-render" docs/images/moving_cameras.yaml --render turn --step "$n" \
    -o "docs/images/moving_turn_$(printf %04d "$n")" --quiet
done
for n in 0 15 30 45 60; do
  "$build/bin/tessera-render" docs/images/moving_cameras.yaml --render fly --step "$n" \
    -o "docs/images/moving_fly_$(printf %04d "$n")" --quiet
done
ls -l docs/images/*.png
