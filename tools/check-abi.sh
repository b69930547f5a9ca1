#!/usr/bin/env bash
# Compares the ABI of a built libnclink.so with the last release's, kept in
# cmake/abi/. Additions are fine; a change that breaks programs built against
# the release fails. Uses abigail-tools (Debian package).
#
# Two depths:
# - symbols (default, run by CI): the exported symbol table. Catches a removed
#   or renamed function, a changed signature (C++ mangling carries the
#   parameter types), a removed variable. Fast (well under a second) and the
#   baseline is small (cmake/abi/libnclink.symbols.abi).
# - --types: the whole type graph reachable from include/nclink (struct
#   layouts, vtables, enumerators). Needs the library's debug info; abidw takes
#   minutes and the dump is tens of MB (nlohmann::json's templates), so it is
#   a release step, not a CI test: its baseline is written beside the release
#   (cmake/abi/libnclink.types.abi, not in git).
#
#   tools/check-abi.sh [--types] LIB                  compare LIB with the baseline
#   tools/check-abi.sh [--types] --update LIB         write LIB's ABI as the new baseline (at a release)
#   tools/check-abi.sh [--types] --baseline FILE LIB  compare with another baseline (tests)
# Exit: 0 compatible, 1 incompatible (the report says what), 2 usage or tools missing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
depth=symbols
update=0
baseline=
while (($#)); do
  case $1 in
    --update) update=1; shift ;;
    --types) depth=types; shift ;;
    --baseline) baseline=$2; shift 2 ;;
    -*) echo "check-abi: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
baseline=${baseline:-$root/cmake/abi/libnclink.$depth.abi}
lib=${1:-}
[[ -n $lib && -f $lib ]] || { echo "usage: check-abi.sh [--types] [--update|--baseline FILE] LIB" >&2; exit 2; }
command -v abidw >/dev/null && command -v abidiff >/dev/null ||
  { echo "check-abi: abidw/abidiff not found (Debian package abigail-tools)" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dump() {
  if [[ $depth == types ]]; then
    # --drop-private-types: types not reachable from the public headers are
    # not part of the contract; no paths, so the file does not name the build.
    abidw --headers-dir "$root/include" --drop-private-types --no-corpus-path --no-comp-dir-path "$1"
  else
    # Without debug info abidw records the ELF symbol table only.
    objcopy --strip-debug "$1" "$work/lib.so"
    abidw --no-corpus-path --no-comp-dir-path "$work/lib.so"
  fi
}

if ((update)); then
  mkdir -p "$(dirname "$baseline")"
  dump "$lib" >"$baseline"
  echo "check-abi: $depth baseline written to ${baseline#"$root"/}"
  exit 0
fi
[[ -f $baseline ]] || { echo "check-abi: no baseline $baseline (tools/check-abi.sh --update at a release)" >&2; exit 2; }

dump "$lib" >"$work/current.abi"
set +e
report=$(abidiff --no-added-syms "$baseline" "$work/current.abi" 2>&1)
rc=$?
set -e
# abidiff's exit status is a bit set: 1 error, 2 usage, 4 ABI change,
# 8 incompatible ABI change. Only 8 (and errors) fail; a compatible change
# (4: e.g. a new enumerator at the end) is reported.
if ((rc & 3)); then echo "$report"; echo "check-abi: abidiff failed ($rc)" >&2; exit 2; fi
if ((rc & 8)); then
  echo "$report"
  echo "check-abi: INCOMPATIBLE with the last release (${baseline#"$root"/}): programs built against it break" >&2
  exit 1
fi
((rc & 4)) && echo "$report"
echo "check-abi: $depth compatible with ${baseline#"$root"/}"
