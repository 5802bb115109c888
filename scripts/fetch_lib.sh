# shellcheck shell=bash
# The steps scripts/fetch_ct.sh and scripts/fetch_mri.sh share (sourced by them, not run): a
# volume already there with its recorded sha256 ends the fetch; a Debian package comes from a
# local file or from `apt-get download` and is unpacked for the caller to pick its file from.
# Exit status, for the calling script: 0 when the volume is already there, 3 when the package
# cannot be downloaded (callers skip those benchmarks), 1 for a local file that is not a
# readable .deb.

# fetch_present TAG RAW SHA256: ends the script (exit 0) when RAW exists with that sha256.
fetch_present() {
  if [ -f "$2" ] && echo "$3  $2" | sha256sum --check --status; then
    echo "$1: $2 already present (sha256 ok)"
    exit 0
  fi
}

# fetch_deb TAG PACKAGE VAR DEB_SHA256 DIR: unpacks the package into DIR/pkg, taking the .deb
# from the file named by environment variable VAR when it is set, else `apt-get download
# PACKAGE` into DIR. A package whose sha256 is not DEB_SHA256 is only noted: the caller checks
# the volume it extracts.
fetch_deb() {
  local tag=$1 pkg=$2 var=$3 sha=$4 dir=$5 deb
  local local_deb="${!var:-}"
  if [ -n "$local_deb" ]; then
    [ -f "$local_deb" ] || { echo "$tag: $var=$local_deb is not a file" >&2; exit 1; }
    deb="$local_deb"
  else
    if ! (cd "$dir" && apt-get download "$pkg" >"$dir/apt.log" 2>&1); then
      echo "$tag: apt-get download $pkg failed (no network or package index?):" >&2
      tail -n 3 "$dir/apt.log" >&2 || true
      exit 3
    fi
    deb="$(ls "$dir/$pkg"_*.deb)"
  fi
  if echo "$sha  $deb" | sha256sum --check --status; then
    echo "$tag: $(basename "$deb") (sha256 as recorded)"
  else
    echo "$tag: note: $(basename "$deb") differs from the recorded package; checking the volume itself"
  fi
  dpkg-deb -x "$deb" "$dir/pkg" 2>"$dir/dpkg.log" ||
    { echo "$tag: $deb is not a readable .deb: $(head -n 1 "$dir/dpkg.log")" >&2; exit 1; }
}

# fetch_install TAG FILE SHA256 RAW: FILE must have that sha256 (else exit 1); it is then copied
# to RAW through RAW.tmp (a reader never sees a half-written RAW), RAW's directory made.
fetch_install() {
  echo "$3  $2" | sha256sum --check --status ||
    { echo "$1: $(basename "$2") sha256 mismatch (expected $3)" >&2; exit 1; }
  mkdir -p "$(dirname "$4")"
  cp "$2" "$4.tmp" && mv "$4.tmp" "$4"
}
