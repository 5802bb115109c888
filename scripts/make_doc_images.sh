#!/usr/bin/env bash
# The pictures of docs/config.md, each made from a config under docs/images/ that says how:
#   "distance: fit"   docs/images/distance_fit_{wide,square,tall}.png   (distance_fit.yaml)
#   "Moving cameras"  docs/images/moving_turn_NNNN.png, a turning orbit, and
#                     docs/images/moving_fly_NNNN.png, a keyframed fly-in (moving_cameras.yaml)
#   "annotations:"    docs/images/annotations.png (annotations.yaml, on synthetic blobs)
#   "The smallest config" docs/images/minimal.png (minimal.yaml, the same blobs)
#   README.md         docs/images/heat_annotated.png: tessera-heat with configs/heat_movie.yaml
#                     (turning camera, title, step text, colour bar), its frame of step 80
#   docs/miniapp.md   docs/images/heat_amr.png: tessera-heat --amr --levels 3 with
#                     configs/heat_amr.yaml on 2 ranks, its image of step 40; and
#                     docs/images/heat_shell.png: tessera-heat-shell (a curvilinear cylindrical
#                     shell, configs/heat_shell.yaml) on 2 ranks, its image of step 60
# The first two render a linear ramp that tessera-synth writes to /tmp/ramp.raw. Builds
# tessera-synth, tessera-render and tessera-heat first when they are missing. Takes about
# twenty seconds.
#
#   scripts/make_doc_images.sh          environment: BUILD_DIR (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${BUILD_DIR:-build}"
for exe in tessera-synth tessera-render tessera-heat tessera-heat-shell; do
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
# The smallest config: a field name alone, every default (minimal.yaml), at 256x256
"$build/bin/tessera-render" docs/images/minimal.yaml --width 256 --height 256 -o docs/images/minimal.png --quiet
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
# The README's frame: the heat demo's movie config, 80 steps on 2 ranks (bit-identical for any
# rank count), the frame of step 80
export OMPI_ALLOW_RUN_AS_ROOT="${OMPI_ALLOW_RUN_AS_ROOT:-1}" OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="${OMPI_ALLOW_RUN_AS_ROOT_CONFIRM:-1}"
rm -rf /tmp/tessera_heat_frame
mpirun --oversubscribe -n 2 "$build/bin/tessera-heat" --config configs/heat_movie.yaml --steps 80 \
  --output-dir /tmp/tessera_heat_frame >/dev/null
cp /tmp/tessera_heat_frame/heat_turn_000080.png docs/images/heat_annotated.png
# The refining miniapp's picture: three levels around the first source, step 40
rm -rf /tmp/tessera_heat_amr
mpirun --oversubscribe -n 2 "$build/bin/tessera-heat" --config configs/heat_amr.yaml --amr --levels 3 \
  --steps 40 --grid 32 32 32 --output-dir /tmp/tessera_heat_amr >/dev/null
cp /tmp/tessera_heat_amr/heat_amr_000040.png docs/images/heat_amr.png
# The curvilinear miniapp's picture: the cylindrical shell, step 60 (bit-identical for any rank count)
rm -rf /tmp/tessera_heat_shell
mpirun --oversubscribe -n 2 "$build/bin/tessera-heat-shell" --steps 60 --output-dir /tmp/tessera_heat_shell >/dev/null
cp /tmp/tessera_heat_shell/heat_shell_000060.png docs/images/heat_shell.png
ls -l docs/images/*.png
