#!/usr/bin/env bash
# Fetches a real head CT for the benchmarks: "Cranium" (ProMED CT 0051, 256 x 256 x 108 int16,
# spacing 0.957 x 0.957 x 1.5 mm) from the Debian package invesalius-examples, and writes it as
# a raw volume with a YAML volume block:
#
#   data/ct/cranium.raw         int16 little-endian, x fastest, 256 x 256 x 108 (14,155,776 bytes)
#   data/ct/cranium_volume.yaml the matching `volume:` block (docs/config.md)
#
#   bash scripts/fetch_ct.sh [DEST_DIR]        (default data/ct; CT_DEB=/path/to.deb skips apt)
#
# The package (about 19 MB) is fetched with `apt-get download` (no root needed beyond apt's
# own cache). Cranium.inv3 is a gzip'd tar holding main.plist (dtype, shape, spacing) and
# matrix.dat (the raw int16 array, C order z, y, x: already a raw volume with x fastest), so the
# conversion is a check of main.plist and of matrix.dat's sha256, then a copy.
# Exit status: 0 on success or if the volume is already there; 3 if the package cannot be
# fetched (callers skip the CT parts); 1 on any other failure (e.g. a checksum mismatch). The
# steps it shares with scripts/fetch_mri.sh are in scripts/fetch_lib.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
dest="${1:-data/ct}"
raw="$dest/cranium.raw"
# sha256 of matrix.dat inside Cranium.inv3 (invesalius-examples 3.1.99998-4, Debian 12).
matrix_sha256=d87fd5e6aaf2c4fdf4f3fe28ee3335192fc2464ed8e9682fc78530cb837938da
# For information: sha256 of the .deb this was computed from.
deb_sha256=f2f14bdfef6dc3812eafc5013d133c6c18370aaab5666b78d54af2e7db432f97

source scripts/fetch_lib.sh
fetch_present fetch_ct "$raw" "$matrix_sha256"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Fetch and unpack the package: .deb -> Cranium.inv3 -> main.plist + matrix.dat
fetch_deb fetch_ct invesalius-examples CT_DEB "$deb_sha256" "$tmp"
inv3="$(find "$tmp/pkg" -name 'Cranium.inv3' | head -n 1)"
[ -n "$inv3" ] || { echo "fetch_ct: Cranium.inv3 not found in the package" >&2; exit 1; }
mkdir -p "$tmp/inv3"
tar -xzf "$inv3" -C "$tmp/inv3"
plist="$(find "$tmp/inv3" -name main.plist | head -n 1)"
matrix="$(dirname "$plist")/matrix.dat"

# Check the header: int16, shape (z, y, x) = (108, 256, 256)
python3 - "$plist" <<'PY'
import plistlib, sys
p = plistlib.load(open(sys.argv[1], "rb"))
m = p["matrix"]
assert m["dtype"] == "int16", m["dtype"]
assert list(m["shape"]) == [108, 256, 256], m["shape"]
print("fetch_ct: %s, %s, shape (z,y,x) %s, spacing %s, scalar range %s"
      % (p.get("name"), p.get("modality"), m["shape"], p["spacing"], p.get("scalar_range")))
PY

# Write the raw volume and its YAML block
fetch_install fetch_ct "$matrix" "$matrix_sha256" "$raw"
cat > "$dest/cranium_volume.yaml" <<YAML
# Cranium (invesalius-examples), written by scripts/fetch_ct.sh. Values are Hounsfield units
# (-1024 .. 3033); +z runs from the first axial slice to the last.
volume:
  file: cranium.raw
  dims: [256, 256, 108]
  dtype: int16
  spacing: [0.9570312, 0.9570312, 1.5]
  byte_order: little
YAML
echo "fetch_ct: wrote $raw (256 x 256 x 108 int16, sha256 ok) and $dest/cranium_volume.yaml"
