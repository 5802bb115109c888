#!/usr/bin/env bash
# Re-makes the pictures of docs/config.md in docs/images from the configs beside them
# ("distance: fit" and "annotations:"), with the commands that page gives.
# Usage: scripts/make_doc_images.sh [BUILD_DIR]   (default: build; tessera-synth and
# tessera-render must be built there). The volumes go to /tmp, where the configs read them.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/bin"
for exe in tessera-synth tessera-render; do
  [ -x "$bin/$exe" ] || { echo "make_doc_images: $bin/$exe is missing (build it first)" >&2; exit 1; }
done

"$bin/tessera-synth" /tmp/ramp.raw --dims 32 32 32 --kind linear
"$bin/tessera-render" docs/images/distance_fit.yaml -o docs/images/distance_fit

"$bin/tessera-synth" /tmp/blobs.raw --dims 64 64 64 --kind blobs
"$bin/tessera-render" docs/images/annotations.yaml --step 120 -o docs/images/annotations.png
ls -l docs/images/*.png
