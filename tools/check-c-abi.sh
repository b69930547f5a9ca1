#!/usr/bin/env bash
# Compares the C ABI of a built libnclink.so (the nclink_* functions of
# include/nclink/nclink.h and every type they reach, the driver plugin structs
# of driver_plugin.h among them) with the baseline in cmake/abi/. Any change
# fails, also an append that the growth rules allow: docs/abi.md says how an
# append is reviewed and recorded (--update). Needs abigail-tools (Debian) and
# a library with debug info (RelWithDebInfo).
#
#   tools/check-c-abi.sh LIB                  compare LIB with cmake/abi/libnclink.c.abi
#   tools/check-c-abi.sh --update LIB         write LIB's C ABI as the baseline
#   tools/check-c-abi.sh --baseline FILE LIB  compare with another dump (tests)
#   tools/check-c-abi.sh --dump LIB           print LIB's C ABI dump
# Exit: 0 equal, 1 changed (the report says what), 2 usage, tools missing or
# no debug info.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
mode=compare
baseline=$root/cmake/abi/libnclink.c.abi
while (($#)); do
  case $1 in
    --update) mode=update; shift ;;
    --dump) mode=dump; shift ;;
    --baseline) baseline=$2; shift 2 ;;
    -*) echo "check-c-abi: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
lib=${1:-}
[[ -n $lib && -f $lib ]] || { echo "usage: check-c-abi.sh [--update|--dump|--baseline FILE] LIB" >&2; exit 2; }
command -v abidw >/dev/null && command -v abidiff >/dev/null ||
  { echo "check-c-abi: abidw/abidiff not found (Debian package abigail-tools)" >&2; exit 2; }
# grep reads to the end: `grep -q` would quit at the match, readelf would
# die of SIGPIPE, and pipefail would call a library with debug info one
# without (seen on this project's test machine, one run in two).
readelf -S "$lib" | grep '\.debug_info' >/dev/null ||
  { echo "check-c-abi: $lib has no debug info (build RelWithDebInfo or Debug)" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Keep only the C API: functions and variables named nclink_* (C++ symbols
# are mangled, _ZN6nclink...); abidiff compares those and the types they
# reach. (The dump also lists declarations the library's translation units
# saw, which no nclink_ function reaches: they never make a difference. A
# --header-file filter would drop them but also turns the C structs into
# declarations without layout, so it is not used.) The opaque handles
# (nclink_adapter, nclink_channel: nclink.h declares them, callers hold only
# pointers) are dropped: their insides are C++ objects that may change in any
# release without touching the binary contract.
cat >"$work/c-only.suppr" <<'SUPPR'
[suppress_function]
  symbol_name_not_regexp = ^nclink_
  drop = yes
[suppress_variable]
  symbol_name_not_regexp = ^nclink_
  drop = yes
[suppress_type]
  type_kind = struct
  name_regexp = ^nclink_(adapter|channel)$
  drop = yes
SUPPR
dump() {
  abidw --suppressions "$work/c-only.suppr" --no-corpus-path --no-comp-dir-path --no-show-locs --no-elf-needed \
    --type-id-style hash "$1"
}

case $mode in
  dump) dump "$lib"; exit 0 ;;
  update)
    dump "$lib" >"$baseline"
    grep -q "elf-symbol name='nclink_" "$baseline" || { echo "check-c-abi: the dump has no nclink_ function" >&2; exit 2; }
    echo "check-c-abi: baseline written to ${baseline#"$root"/}"
    exit 0 ;;
esac
[[ -f $baseline ]] || { echo "check-c-abi: no baseline $baseline (tools/check-c-abi.sh --update LIB)" >&2; exit 2; }
dump "$lib" >"$work/current.abi"
grep -q "elf-symbol name='nclink_" "$work/current.abi" ||
  { echo "check-c-abi: $lib exports no nclink_ function: not a library with the C API" >&2; exit 2; }
set +e
report=$(abidiff --no-added-syms "$baseline" "$work/current.abi" 2>&1)
rc=$?
set -e
# abidiff's status is a bit set: 1 error, 2 usage, 4 ABI change, 8 incompatible.
if ((rc & 3)); then echo "$report"; echo "check-c-abi: abidiff failed ($rc)" >&2; exit 2; fi
# New functions are additions (--no-added-syms hides them); any other
# difference is a change of the binary contract.
if ((rc & 12)); then
  echo "$report"
  echo "check-c-abi: the C ABI differs from ${baseline#"$root"/} (docs/abi.md: appends are reviewed, then --update)" >&2
  exit 1
fi
echo "check-c-abi: the C ABI matches ${baseline#"$root"/}"
