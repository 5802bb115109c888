#!/usr/bin/env bash
# Formats the tracked C and C++ sources with clang-format and the repository's .clang-format,
# leaving out the files listed in .clang-format-ignore (Fortran and other languages are never
# touched).
#
#   bash scripts/format.sh [PATH ...]            rewrite the files in place
#   bash scripts/format.sh --check [PATH ...]    change nothing; list the files that differ from
#                                                their formatted form and exit 1 if there are any
#
# PATHs (files or folders) narrow it to those parts of the tree; default: the whole tree.
# CLANG_FORMAT names the program (default: clang-format). The style is written for
# clang-format 14 (Debian 12); other versions format some constructs differently, so a check
# is only meaningful with version 14.
set -euo pipefail
cd "$(dirname "$0")/.."

check=0
if [ "${1:-}" = "--check" ]; then
  check=1
  shift
fi
case "${1:-}" in
  -h|--help) sed -n '2,13s/^# \{0,1\}//p' "$0"; exit 0 ;;
  -*) echo "format.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
esac

cf="${CLANG_FORMAT:-clang-format}"
if ! command -v "$cf" > /dev/null; then
  echo "format.sh: $cf not found (Debian/Ubuntu: apt-get install clang-format)" >&2
  exit 2
fi
version=$("$cf" --version | sed -n 's/.*version \([0-9][0-9]*\)\..*/\1/p')
if [ "$version" != 14 ]; then
  echo "format.sh: note: $cf is version ${version:-unknown}; the style is written for version 14" >&2
fi

# The patterns of .clang-format-ignore (comments and blank lines dropped).
ignore=()
if [ -f .clang-format-ignore ]; then
  while IFS= read -r line || [ -n "$line" ]; do
    line="${line#"${line%%[![:space:]]*}"}"
    line="${line%"${line##*[![:space:]]}"}"
    [ -z "$line" ] || [ "${line:0:1}" = "#" ] || ignore+=("$line")
  done < .clang-format-ignore
fi

files=()
while IFS= read -r -d '' f; do
  case "$f" in
    *.c|*.cc|*.cpp|*.cxx|*.h|*.hh|*.hpp|*.inl) ;;
    *) continue ;;
  esac
  skip=0
  for pattern in ${ignore[@]+"${ignore[@]}"}; do
    # shellcheck disable=SC2053  # the pattern is a glob on purpose
    if [[ "$f" == $pattern ]]; then skip=1; break; fi
  done
  [ "$skip" = 1 ] || [ ! -f "$f" ] || files+=("$f")
done < <(git ls-files -z -- "${@:-.}")

if [ "${#files[@]}" = 0 ]; then
  echo "format.sh: no C or C++ files to format" >&2
  exit 0
fi

if [ "$check" = 0 ]; then
  printf '%s\0' "${files[@]}" | xargs -0 "$cf" -i --style=file
  exit 0
fi

differ=0
for f in "${files[@]}"; do
  if ! "$cf" --style=file "$f" | cmp -s - "$f"; then
    echo "$f"
    differ=$((differ + 1))
  fi
done
if [ "$differ" -gt 0 ]; then
  echo "format.sh: $differ of ${#files[@]} files differ from their clang-format form (bash scripts/format.sh fixes them)" >&2
  exit 1
fi
echo "format.sh: ${#files[@]} files formatted" >&2
