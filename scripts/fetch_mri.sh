#!/usr/bin/env bash
# Fetches a real brain MRI for the benchmarks: "ch2better", the Colin27 T1-weighted head (one
# subject, 27 scans averaged; 301 x 370 x 316 uint8, spacing 0.5 x 0.5 x 0.5 mm, outside of the
# head zeroed) from the Debian package mricron-data, and writes it as a raw volume with a YAML
# volume block:
#
#   data/mri/ch2better.raw          uint8, x fastest, 301 x 370 x 316 (35,192,920 bytes)
#   data/mri/ch2better_volume.yaml  the matching `volume:` block (docs/config.md)
#
#   bash scripts/fetch_mri.sh [DEST_DIR]      (default data/mri; MRI_DEB=/path/to.deb skips apt)
#
# The package (about 16 MB) is fetched with `apt-get download` (no root needed beyond apt's
# own cache). templates/ch2better.nii.gz is a gzip'd NIfTI-1 file: a 348-byte header (dims,
# datatype, voxel size, offset of the data), then the voxels with x fastest. The conversion reads
# and checks the header (Python standard library only), writes the voxels from vox_offset on as
# the raw volume and checks its sha256. Axes as in the file: +x to the subject's right, +y to
# the front, +z up (its qform and sform are diagonal with positive spacing).
# Exit status: 0 on success or if the volume is already there; 3 if the package cannot be
# fetched (callers skip the MRI parts); 1 on any other failure (e.g. a checksum mismatch or a
# header that is not the one expected). The steps it shares with scripts/fetch_ct.sh are in
# scripts/fetch_lib.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
dest="${1:-data/mri}"
raw="$dest/ch2better.raw"
# sha256 of the voxels of ch2better.nii.gz (mricron-data 1.2.20211006+dfsg-4, Debian 12).
raw_sha256=f3eeb663ed3d92277d1108f87ef7f04fcad0b06cfb1f93753dbe35689e1a76b5
# For information: sha256 of the .deb this was computed from.
deb_sha256=d40aa0ed66cf89bf6cafa049ad3884703c9d975c2ee2737525b7196528df9d6f

source scripts/fetch_lib.sh
fetch_present fetch_mri "$raw" "$raw_sha256"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Fetch and unpack the package: .deb -> ch2better.nii.gz
fetch_deb fetch_mri mricron-data MRI_DEB "$deb_sha256" "$tmp"
nii="$(find "$tmp/pkg" -name 'ch2better.nii.gz' | head -n 1)"
[ -n "$nii" ] || { echo "fetch_mri: ch2better.nii.gz not found in the package" >&2; exit 1; }

# Check the NIfTI-1 header and write the voxels: 3-D uint8 301 x 370 x 316, 0.5 mm, unscaled
python3 - "$nii" "$tmp/ch2better.raw" <<'PY'
import gzip, struct, sys

src, out = sys.argv[1], sys.argv[2]
DTYPES = {2: ("uint8", 1), 4: ("int16", 2), 16: ("float32", 4), 64: ("float64", 8), 512: ("uint16", 2)}


def fail(msg):
    sys.exit(f"fetch_mri: ch2better.nii.gz: {msg}")


with gzip.open(src, "rb") as f:
    hdr = f.read(348)
    if len(hdr) < 348:
        fail(f"{len(hdr)} bytes, shorter than a NIfTI-1 header (348)")
    if struct.unpack("<i", hdr[0:4])[0] != 348:
        fail(f"sizeof_hdr {struct.unpack('<i', hdr[0:4])[0]} (little-endian), expected 348: "
             "not a little-endian NIfTI-1 file")
    if hdr[344:348] != b"n+1\0":
        fail(f"magic {hdr[344:348]!r}, expected b'n+1\\x00' (a single-file NIfTI-1)")
    dim = struct.unpack("<8h", hdr[40:56])
    datatype, bitpix = struct.unpack("<2h", hdr[70:74])
    pixdim = struct.unpack("<8f", hdr[76:108])
    vox_offset = struct.unpack("<f", hdr[108:112])[0]
    scl_slope, scl_inter = struct.unpack("<2f", hdr[112:120])
    if dim[0] != 3 or any(d < 1 for d in dim[1:4]):
        fail(f"dim {dim[:dim[0] + 1] if 0 < dim[0] < 8 else dim}: expected a 3-D volume")
    if datatype not in DTYPES:
        fail(f"datatype {datatype}: expected one of "
             f"{', '.join(f'{k} ({v[0]})' for k, v in DTYPES.items())}")
    if DTYPES[datatype][1] * 8 != bitpix:
        fail(f"datatype {datatype} ({DTYPES[datatype][0]}) with bitpix {bitpix}, expected "
             f"{DTYPES[datatype][1] * 8}")
    dtype, size = DTYPES[datatype]
    if scl_slope not in (0.0, 1.0) or scl_inter != 0.0:
        fail(f"scl_slope {scl_slope}, scl_inter {scl_inter}: scaled values are not converted here")
    if vox_offset < 348 or vox_offset != int(vox_offset):
        fail(f"vox_offset {vox_offset}: expected a whole number of bytes >= 348")
    nx, ny, nz = dim[1:4]
    spacing = pixdim[1:4]
    if any(not (s > 0) for s in spacing):
        fail(f"pixdim {spacing}: expected positive voxel sizes")
    # The one volume this script is for
    expect = ((301, 370, 316), "uint8", (0.5, 0.5, 0.5))
    if ((nx, ny, nz), dtype, spacing) != expect:
        fail(f"{nx}x{ny}x{nz} {dtype} spacing {spacing}, expected {expect[0]} {expect[1]} {expect[2]}")
    f.read(int(vox_offset) - 348)  # the extension bytes, if any
    n = nx * ny * nz * size
    data = f.read(n)
    if len(data) != n:
        fail(f"{len(data)} voxel bytes after offset {int(vox_offset)}, expected {n}")
    if f.read(1):
        fail(f"bytes left after the {n} voxel bytes")
with open(out, "wb") as o:
    o.write(data)
print(f"fetch_mri: NIfTI-1 {nx} x {ny} x {nz} {dtype}, spacing {spacing} mm, vox_offset "
      f"{int(vox_offset)}, values {min(data)} .. {max(data)}")
PY

# Write the raw volume and its YAML block
fetch_install fetch_mri "$tmp/ch2better.raw" "$raw_sha256" "$raw"
cat > "$dest/ch2better_volume.yaml" <<YAML
# ch2better (Colin27 T1, mricron-data), written by scripts/fetch_mri.sh. Values are T1 intensities
# 0 .. 255 (0 outside the head); +x to the subject's right, +y to the front, +z up.
volume:
  file: ch2better.raw
  dims: [301, 370, 316]
  dtype: uint8
  spacing: [0.5, 0.5, 0.5]
  byte_order: little
YAML
echo "fetch_mri: wrote $raw (301 x 370 x 316 uint8, sha256 ok) and $dest/ch2better_volume.yaml"
