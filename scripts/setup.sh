#!/usr/bin/env bash
# Installs the Debian 12 packages Tessera builds with (only those missing), then configures
# and builds into ./build. Safe to run again; used by demo.sh, test.sh and CI.
set -euo pipefail
cd "$(dirname "$0")/.."

pkgs=(build-essential cmake pkg-config libtbb-dev libopenexr-dev libglm-dev libyaml-cpp-dev
      catch2 libopenmpi-dev openmpi-bin libpng-dev gfortran
      libfreetype-dev fonts-dejavu-core valgrind clang-format)
# Opt-in extras, not needed by the normal build:
#   TESSERA_SETUP_FUZZ=1        clang and its libFuzzer / sanitizer runtimes (scripts/fuzz.sh)
#   TESSERA_SETUP_DEMO=1        ffmpeg, which turns the heat demo's frames into MP4s (demo.sh)
#   TESSERA_SETUP_SKIP_BUILD=1  install packages only, do not configure or build ./build
#   TESSERA_SETUP_TARGETS="a b" build only these targets (demo.sh: the three programs)
if [ "${TESSERA_SETUP_FUZZ:-0}" = 1 ]; then pkgs+=(clang libclang-rt-14-dev); fi
if [ "${TESSERA_SETUP_DEMO:-0}" = 1 ]; then pkgs+=(ffmpeg); fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

[ "${TESSERA_SETUP_SKIP_BUILD:-0}" = 1 ] && exit 0

build_type="${TESSERA_BUILD_TYPE:-Release}"
cmake -S . -B build -DCMAKE_BUILD_TYPE="$build_type" ${TESSERA_CMAKE_ARGS:-}
# shellcheck disable=SC2086  # a list of target names
cmake --build build -j"$(nproc)" ${TESSERA_SETUP_TARGETS:+--target $TESSERA_SETUP_TARGETS}
