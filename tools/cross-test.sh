#!/usr/bin/env bash
# The cross leg: builds the terminal library, its unit tests and nclink-sim
# for another CPU with Debian 12's cross compiler, runs the unit tests under
# qemu-user, and runs one real-broker check: that CPU's nclink-sim (under
# qemu) answering Probe/Query/Set, refusing malformed input and streaming its
# sample channels through a NATIVE mosquitto on a free loopback port to a
# NATIVE client (mosquitto_pub/mosquitto_sub speaking NC-Link DTUs); and the
# C firmware example (under qemu) passing the native nclink-conform.
#
#   tools/cross-test.sh aarch64     # 64-bit ARM (preset cross-aarch64, build-aarch64/)
#   tools/cross-test.sh armhf       # 32-bit ARM (preset cross-armhf, build-armhf/)
#
# Installs what it needs (tools/install-deps.sh with NCLINK_WITH_CROSS),
# idempotently. Prints one line "cross-test ARCH: PASS|FAIL ..." at the end
# and exits non-zero on failure. docs/building.md, "Cross-building".
# NCLINK_JOBS (default nproc) sets the build's parallelism; NCLINK_CROSS_TLS
# (ON/OFF) is passed as NCLINK_WITH_TLS when the build has that option;
# NCLINK_CROSS_MODULES (e.g. "core sampling") runs the unit tests of those
# modules only.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"

arch=${1:-}
case "$arch" in
  aarch64 | arm64) arch=aarch64 deb=arm64 qemu=qemu-aarch64 ;;
  armhf | arm) arch=armhf deb=armhf qemu=qemu-arm ;;
  *) echo "usage: tools/cross-test.sh aarch64|armhf" >&2; exit 2 ;;
esac
preset=cross-$arch
build=build-$arch
jobs=${NCLINK_JOBS:-$(nproc)}
t0=$(date +%s)
say() { printf '\n== cross-test %s: %s\n' "$arch" "$*"; }
phase_times=()
phase() { phase_times+=("$1 $(( $(date +%s) - t0 ))s"); }

# Whatever fails below, the last line says so.
result=FAIL
summary="stopped early"
finish() {
  local rc=${1:-$?}
  if [[ $result == PASS && $rc -eq 0 ]]; then
    printf '\ncross-test %s: PASS (%s) in %ss [elapsed after %s]\n' "$arch" "$summary" "$(( $(date +%s) - t0 ))" "${phase_times[*]}"
  else
    printf '\ncross-test %s: FAIL (%s) in %ss [elapsed after %s]\n' "$arch" "$summary" "$(( $(date +%s) - t0 ))" "${phase_times[*]}" >&2
    [[ $rc -ne 0 ]] || rc=1
  fi
  exit "$rc"
}
trap finish EXIT

say "installing the cross compiler, the $deb libraries and qemu-user (if missing)"
NCLINK_WITH_CROSS=$deb NCLINK_WITH_OPCUA=0 tools/install-deps.sh
phase install

# qemu-user runs the target's programs: ctest through
# CMAKE_CROSSCOMPILING_EMULATOR (set by the toolchain file), so binfmt_misc
# is not needed. Never with -L /usr/<triplet> (docs/building.md).
if ! command -v "$qemu" >/dev/null; then echo "cross-test: $qemu not found (apt install qemu-user)" >&2; exit 1; fi
if [[ -n "${QEMU_LD_PREFIX:-}" ]]; then
  echo "cross-test: QEMU_LD_PREFIX is set ($QEMU_LD_PREFIX); unset it, the multiarch loader finds the libraries" >&2
  exit 1
fi

say "configuring $build (preset $preset)"
mkdir -p "$build"
cmake --preset "$preset" >"$build/cross-configure.log" 2>&1 || { cat "$build/cross-configure.log"; exit 1; }
# Options of the library split, when this tree has them: the terminal
# library only (no plant side), TLS as asked.
extra=()
options=$(cmake -N -LH "$build" 2>/dev/null || true)
if grep -q '^NCLINK_BUILD_PLANT:' <<<"$options"; then extra+=(-DNCLINK_BUILD_PLANT=OFF); fi
if grep -q '^NCLINK_WITH_TLS:' <<<"$options"; then extra+=(-DNCLINK_WITH_TLS="${NCLINK_CROSS_TLS:-ON}"); fi
# No debug information by default: the leg checks behaviour on the target,
# and -g made a cross compile 65 % slower here (18.1 s against 11.0 s for
# one unit-test file), the largest part of the leg on a fresh machine.
# NCLINK_CROSS_DEBUG_INFO=1 keeps RelWithDebInfo's -g (to debug under qemu).
if [[ "${NCLINK_CROSS_DEBUG_INFO:-0}" == 0 ]]; then
  extra+=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -DNDEBUG")
else
  extra+=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g -DNDEBUG")
fi
if ((${#extra[@]})); then
  cmake "$build" "${extra[@]}" >>"$build/cross-configure.log" 2>&1 || { cat "$build/cross-configure.log"; exit 1; }
fi
phase configure

# The terminal library's modules (src/layers.txt, up to the gateway) and the
# unit-test programs of those that have one.
# NCLINK_CROSS_MODULES="core sampling" narrows the unit tests to those modules.
terminal_modules=(core model values protocol driver transport feature sampling events methods adapter embed gateway)
if [[ -n "${NCLINK_CROSS_MODULES:-}" ]]; then read -ra terminal_modules <<<"$NCLINK_CROSS_MODULES"; fi
targets=$(cmake --build "$build" --target help 2>/dev/null | sed -n 's/^\.\.\. \([^ ]*\).*/\1/p')
has_target() { grep -qx "$1" <<<"$targets"; }
build_targets=(nclink-sim)
if has_target nclink_shared; then build_targets+=(nclink_shared); fi
# The C firmware example (examples/c-firmware: C11 over nclink.h).
if has_target nclink_c_firmware; then build_targets+=(nclink_c_firmware); fi
tested=()
for m in "${terminal_modules[@]}"; do
  if has_target "test_$m"; then build_targets+=("test_$m"); tested+=("$m"); fi
done
say "building ${build_targets[*]} (-j$jobs)"
cmake --build "$build" -j "$jobs" --target "${build_targets[@]}"
phase build

say "unit tests of ${tested[*]} under $qemu"
regex="^($(IFS='|'; echo "${tested[*]}")):"
# ctest's own report goes to a file: run from tools/run-tests.sh, the native
# suite's closing line stays the last one a reader of the whole run sees.
unit_log=$build/cross-unit.log
set +e
ctest --test-dir "$build" -R "$regex" -j "$jobs" --output-on-failure --timeout 600 >"$unit_log" 2>&1
unit_rc=$?
set -e
total=$(sed -n 's/.* tests failed out of \([0-9]*\)$/\1/p' "$unit_log" | tail -n 1)
failed_n=$(sed -n 's/.* \([0-9]*\) tests failed out of [0-9]*$/\1/p' "$unit_log" | tail -n 1)
phase unit
if [[ $unit_rc -ne 0 || -z $total || $total -eq 0 ]]; then
  tail -n 150 "$unit_log"
  summary="unit tests under $qemu: ${failed_n:-?} of ${total:-0} failed (log: $unit_log)"
  exit 1
fi
unit_line="$((total - failed_n)) of $total unit tests passed under $qemu"
echo "  $unit_line (ctest's report: $unit_log)"

# ---------------------------------------------------------------- integration
say "integration: $arch nclink-sim under $qemu, native mosquitto and its clients"
work=$(mktemp -d)
source tools/lib/local_broker.sh
trap 'rc=$?; stop_children; rm -rf "$work"; finish "$rc"' EXIT
start_local_broker || { summary="no free loopback port"; exit 1; }
device=nclink-sim-mill-01

# The target's program, run by qemu-user explicitly (no binfmt needed).
"$qemu" "$build/bin/nclink-sim" --broker "$broker" --log-level warn >"$work/sim.log" 2>&1 &
pids+=($!)

# The native client: mosquitto's own command-line clients, speaking NC-Link
# DTUs (GB/T 41970-2022 8.2) as an application with terminal id "cross".
# Nothing of nclink runs natively, so no native build is needed.
sub() { mosquitto_sub -h 127.0.0.1 -p "$port" -q 1 "$@"; }
pub() { mosquitto_pub -h 127.0.0.1 -p "$port" -q 1 "$@"; }
# request KIND PAYLOAD: publishes on KIND/Request/dev/cross and leaves the
# answer (KIND/Response/dev/cross, 8.2: the request's shape mirrored) in
# $work/answer. A subscriber that was not ready in time gets a second try.
request() {
  local attempt
  for attempt in 1 2 3; do
    sub -t "$1/Response/$device/cross" -C 1 -W 20 >"$work/answer" 2>/dev/null &
    local waiter=$!
    sleep 0.5
    pub -t "$1/Request/$device/cross" -m "$2"
    wait "$waiter" && [[ -s $work/answer ]] && return 0
  done
  return 1
}

passed=0 failed=0
check() {  # check NAME COMMAND...: on failure the last answer is shown
  local name=$1; shift
  : >"$work/answer"
  if "$@" >"$work/out" 2>&1; then
    passed=$((passed + 1)); echo "  ok    $name"
  else
    failed=$((failed + 1)); echo "  FAIL  $name"
    sed 's/^/        /' "$work/out" "$work/answer"
  fi
}
# 8.2.2: the adapter's retained Notify/State says online once it is connected.
# online [DEVICE PID LOG]: by default the simulator's.
online() {
  local dev=${1:-$device} pid=${2:-${pids[1]}} log=${3:-$work/sim.log}
  for _ in $(seq 90); do
    sub -t "Notify/State/$dev" -C 1 -W 2 2>/dev/null | grep -q '"state" *: *"online"' && return 0
    kill -0 "$pid" 2>/dev/null || { cat "$log"; return 1; }
  done
  return 1
}
# 8.2.8 Probe/Query: the model as an object, with its channels and items.
probe() {
  request Probe/Query '{"@id":"p1"}' && grep -q '"@id" *: *"p1"' "$work/answer" &&
    grep -q '"probe" *: *{' "$work/answer" && grep -q '"ch_fast"' "$work/answer" && grep -q '"spindle_speed"' "$work/answer"
}
# 8.2.11 Query: one OK entry with values per item asked.
query() {
  request Query '{"@id":"q1","ids":[{"id":"x_position"},{"id":"spindle_speed"}]}' &&
    [[ $(grep -o '"code" *: *"OK"' "$work/answer" | wc -l) -eq 2 ]] && grep -q '"x_position"' "$work/answer"
}
# 8.2.13 Set, then Query reads the value back.
set_read_back() {
  request Set '{"@id":"s1","values":[{"id":"feed_override","params":{"value":37}}]}' &&
    grep -q '"code" *: *"OK"' "$work/answer" &&
    request Query '{"@id":"q2","ids":[{"id":"feed_override"}]}' &&
    grep -Eq '"values" *: *\[ *37(\.0+)? *\]' "$work/answer"
}
# 8.2.17 Sample DTUs of the model's channels, streamed as the machine runs:
# three of ch_slow and one of ch_fast (6 columns), each with its beginTime.
stream() {
  sub -t "Sample/$device/ch_slow" -C 3 -W 30 >"$work/slow" &&
    sub -t "Sample/$device/ch_fast" -C 1 -W 30 >"$work/fast" &&
    [[ $(grep -c '"beginTime"' "$work/slow") -eq 3 ]] && grep -q '"id" *: *"ch_slow"' "$work/slow" &&
    [[ $(grep -o '"data" *: *\[' "$work/fast" | wc -l) -eq 7 ]]
}
# Bad input: malformed JSON is answered with 412 (table 19), and the
# simulator keeps serving.
refuses_garbage() {
  request Query '{not json' && grep -q '"error" *: *412' "$work/answer" &&
    request Query '{"@id":"q3","ids":[{"id":"status"}]}' && grep -q '"code" *: *"OK"' "$work/answer"
}

# The C firmware example under qemu, checked by the native conformance
# tester (GB/T 41970-2022 chapter 9) when a native build has one
# (tools/run-tests.sh builds it before this leg; NCLINK_NATIVE_BIN names
# another directory). Timeouts allow for the emulation.
firmware_device=acme-cfw-0001
conform_bin=${NCLINK_NATIVE_BIN:-$here/build/bin}/nclink-conform
firmware_conforms() {
  "$qemu" "$build/bin/nclink-c-firmware" --broker "$broker" >"$work/firmware.log" 2>&1 &
  local firmware=$!
  pids+=("$firmware")
  online "$firmware_device" "$firmware" "$work/firmware.log" || { echo "the C firmware did not come online"; return 1; }
  "$conform_bin" --broker "$broker" --device "$firmware_device" --allow-write --method home_axes \
    --timeout-ms 10000 --max-wait-ms 20000 --json "$work/conform.json" ||
    { cat "$work/firmware.log"; return 1; }
}

check "Notify/State online" online
check "Probe/Query: the model" probe
check "Query: two items" query
check "Set feed_override=37, Query reads it back" set_read_back
check "Sample: ch_slow and ch_fast stream" stream
check "bad input answered with 412, still serving" refuses_garbage
if [[ ! -x $build/bin/nclink-c-firmware ]]; then
  echo "  skip  the C firmware example (not built for $arch)"
elif [[ ! -x $conform_bin ]]; then
  echo "  skip  the C firmware example under nclink-conform (no native $conform_bin; build it first or set NCLINK_NATIVE_BIN)"
else
  check "the C firmware example passes nclink-conform" firmware_conforms
fi
stop_children
phase integration
echo "  integration checks: $passed of $((passed + failed)) passed"

summary="$unit_line; integration: $passed of $((passed + failed)) checks passed"
if ((failed == 0 && passed > 0)); then result=PASS; else exit 1; fi
