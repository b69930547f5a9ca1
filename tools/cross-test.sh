#!/usr/bin/env bash
# The cross leg: builds the terminal library, its unit tests and nclink-sim
# for another CPU with Debian 12's cross compiler, runs the unit tests under
# qemu-user, and runs one real-broker check: that CPU's nclink-sim (under
# qemu) answering Probe/Query/Set and streaming sample channels through a
# NATIVE mosquitto on a free loopback port to the NATIVE `nclink` tool.
#
#   tools/cross-test.sh aarch64     # 64-bit ARM (preset cross-aarch64, build-aarch64/)
#   tools/cross-test.sh armhf       # 32-bit ARM (preset cross-armhf, build-armhf/)
#
# Installs what it needs (tools/install-deps.sh with NCLINK_WITH_CROSS),
# idempotently. Prints one line "cross-test ARCH: PASS|FAIL ..." at the end
# and exits non-zero on failure. docs/building.md, "Cross-building".
# NCLINK_JOBS (default nproc) sets the build's parallelism; NCLINK_CROSS_TLS
# (ON/OFF) is passed as NCLINK_WITH_TLS when the build has that option.
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
    printf '\ncross-test %s: PASS (%s) in %ss [%s]\n' "$arch" "$summary" "$(( $(date +%s) - t0 ))" "${phase_times[*]}"
  else
    printf '\ncross-test %s: FAIL (%s) in %ss [%s]\n' "$arch" "$summary" "$(( $(date +%s) - t0 ))" "${phase_times[*]}" >&2
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
if ((${#extra[@]})); then
  cmake "$build" "${extra[@]}" >>"$build/cross-configure.log" 2>&1 || { cat "$build/cross-configure.log"; exit 1; }
fi
phase configure

# The terminal library's modules (src/layers.txt, up to the gateway) and the
# unit-test programs of those that have one.
terminal_modules=(core model values protocol driver transport feature sampling events methods adapter gateway)
targets=$(cmake --build "$build" --target help 2>/dev/null | sed -n 's/^\.\.\. \([^ ]*\).*/\1/p')
has_target() { grep -qx "$1" <<<"$targets"; }
build_targets=(nclink-sim)
if has_target nclink_shared; then build_targets+=(nclink_shared); fi
tested=()
for m in "${terminal_modules[@]}"; do
  if has_target "test_$m"; then build_targets+=("test_$m"); tested+=("$m"); fi
done
say "building ${build_targets[*]} (-j$jobs)"
cmake --build "$build" -j "$jobs" --target "${build_targets[@]}"
phase build

# The native side of the integration check: the `nclink` tool (built by the
# native suite already when run from tools/run-tests.sh).
native_cli=build/bin/nclink
if [[ ! -x $native_cli ]] || ! cmake --build build --target nclink_cli -j "$jobs" >/dev/null 2>&1; then
  say "building the native nclink tool (build/, preset default)"
  [[ -f build/CMakeCache.txt ]] || cmake --preset default >/dev/null
  cmake --build build --target nclink_cli -j "$jobs"
fi
phase native-tool

say "unit tests of ${tested[*]} under $qemu"
regex="^($(IFS='|'; echo "${tested[*]}")): "
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
say "integration: $arch nclink-sim under $qemu, native mosquitto, native nclink tool"
work=$(mktemp -d)
pids=()
stop_all() {
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[i]}" 2>/dev/null || true
    wait "${pids[i]}" 2>/dev/null || true
  done
}
cleanup() { stop_all; rm -rf "$work"; }
trap 'rc=$?; cleanup; finish "$rc"' EXIT

port=""
base=$((20000 + RANDOM % 20000))
for candidate in $(seq "$base" $((base + 200))); do
  if ! (exec 3<>"/dev/tcp/127.0.0.1/$candidate") 2>/dev/null; then port=$candidate; break; fi
done
[[ -n $port ]] || { summary="no free loopback port"; exit 1; }
broker="tcp://127.0.0.1:$port"
device=nclink-sim-mill-01
mosquitto_bin=$(command -v mosquitto || echo /usr/sbin/mosquitto)
{
  echo "listener $port 127.0.0.1"
  echo "allow_anonymous true"
  echo "persistence false"
  cat tools/mosquitto/nclink.conf
} >"$work/mosquitto.conf"
"$mosquitto_bin" -c "$work/mosquitto.conf" >"$work/mosquitto.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && break; sleep 0.1; done

# The target's program, run by qemu-user explicitly (no binfmt needed).
"$qemu" "$build/bin/nclink-sim" --broker "$broker" --log-level warn >"$work/sim.log" 2>&1 &
pids+=($!)
# Under emulation every request is slower: a generous timeout per request.
nclink_t() { "$native_cli" "$2" --broker "$broker" --device "$device" --timeout "$1" "${@:3}"; }
nclink() { nclink_t 10000 "$@"; }

passed=0 failed=0
check() {  # check NAME COMMAND...: the command's output is in $work/out
  local name=$1; shift
  if "$@" >"$work/out" 2>&1; then
    passed=$((passed + 1)); echo "  ok    $name"
  else
    failed=$((failed + 1)); echo "  FAIL  $name"; sed 's/^/        /' "$work/out"
  fi
}
online() {
  for _ in $(seq 120); do
    nclink_t 1000 state 2>/dev/null | grep -q online && return 0
    kill -0 "${pids[1]}" 2>/dev/null || { cat "$work/sim.log"; return 1; }
    sleep 0.5
  done
  return 1
}
probe_has_model() { nclink probe >"$work/probe" && grep -q ch_fast "$work/probe" && grep -q spindle_speed "$work/probe"; }
query_numbers() {
  nclink query x_position spindle_speed >"$work/query" &&
    grep -Eq '^x_position = -?[0-9]' "$work/query" && grep -Eq '^spindle_speed = -?[0-9]' "$work/query"
}
set_and_read_back() {
  nclink set feed_override=37 && nclink query feed_override >"$work/q" && grep -Eq '^feed_override = 37(\.0+)?$' "$work/q"
}
# A dynamic channel (Register/Sample): its rows must arrive, 20 of them.
dynamic_channel() {
  nclink sample x_position y_position --sample-ms 10 --upload-ms 100 --count 20 >"$work/rows" &&
    [[ $(grep -Ec '^[0-9]{4}-' "$work/rows") -ge 20 ]]
}
# A static channel of the model (ch_slow, 100 ms rows): streamed as it runs.
static_channel() { nclink watch --channel ch_slow --count 3 >"$work/watch" && [[ -s $work/watch ]]; }
# Bad input: an unknown item is refused with a code, the simulator keeps serving.
refuses_unknown() { ! nclink query no_such_item >/dev/null 2>&1 && nclink query status >/dev/null; }

check "online (Notify/State)" online
check "Probe/Query: the model" probe_has_model
check "Query: values" query_numbers
check "Set: feed_override=37, read back" set_and_read_back
check "Sample: a dynamic channel streams 20 rows" dynamic_channel
check "Sample: the static channel ch_slow streams" static_channel
check "bad input refused, still serving" refuses_unknown
stop_all
phase integration
echo "  integration checks: $passed of $((passed + failed)) passed"

summary="$unit_line; integration: $passed of $((passed + failed)) checks passed"
if ((failed == 0 && passed > 0)); then result=PASS; else exit 1; fi
