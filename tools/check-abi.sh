#!/usr/bin/env bash
# Compares the ABI of a built libnclink.so with the ABI of the last release,
# kept in cmake/abi/libnclink.abi (abidw of the released library, restricted to
# the public headers). Additions are fine; a change that breaks programs built
# against the release (a removed or changed function, a changed struct layout
# or vtable) fails. Uses abigail-tools (Debian package).
#   tools/check-abi.sh LIB             compare LIB with the baseline
#   tools/check-abi.sh --update LIB    write LIB's ABI as the new baseline (at a release)
#   tools/check-abi.sh --baseline FILE LIB   compare with another baseline (tests)
# Exit: 0 compatible, 1 incompatible (the report says what), 2 usage or tools missing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
baseline=$root/cmake/abi/libnclink.abi
update=0
while (($#)); do
  case $1 in
    --update) update=1; shift ;;
    --baseline) baseline=$2; shift 2 ;;
    -*) echo "check-abi: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
lib=${1:-}
[[ -n $lib && -f $lib ]] || { echo "usage: check-abi.sh [--update|--baseline FILE] LIB" >&2; exit 2; }
command -v abidw >/dev/null && command -v abidiff >/dev/null ||
  { echo "check-abi: abidw/abidiff not found (Debian package abigail-tools)" >&2; exit 2; }

headers=$root/include
# --drop-private-types: types not reachable from the public headers are not
# part of the contract; --no-corpus-path keeps the file free of build paths.
dump() { abidw --headers-dir "$headers" --drop-private-types --no-corpus-path --no-comp-dir-path "$1"; }

if ((update)); then
  mkdir -p "$(dirname "$baseline")"
  dump "$lib" >"$baseline"
  echo "check-abi: baseline written to ${baseline#"$root"/}"
  exit 0
fi
[[ -f $baseline ]] || { echo "check-abi: no baseline $baseline (tools/check-abi.sh --update at a release)" >&2; exit 2; }

current=$(mktemp)
trap 'rm -f "$current"' EXIT
dump "$lib" >"$current"
set +e
report=$(abidiff --no-added-syms "$baseline" "$current" 2>&1)
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
echo "check-abi: compatible with ${baseline#"$root"/}"
