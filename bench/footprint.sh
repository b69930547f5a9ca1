#!/usr/bin/env bash
# Footprint of the terminal library and of one adapter, one table per
# architecture (docs/footprint.md):
#   - libnclink.so stripped, RelWithDebInfo and MinSizeRel, and its NEEDED;
#   - resident memory of nclink-sim (one adapter, the simulated mill, every
#     sample channel running) through a native mosquitto after N seconds;
#   - threads of that process and the names of the adapter's threads;
#   - heap allocations per sample row (sampler thread) and per Sample DTU
#     (whole process, and less libmosquitto's own, measured in the same run)
#     (whole process) after a warm-up (bench/bench_footprint.cpp).
#
#   bench/footprint.sh [--seconds N] [x86_64] [aarch64] [armhf]
#
# Default: 60 s, all three. The ARM programs run under qemu-user: their RSS
# counts only the pages of the emulated program (the host mappings inside
# qemu's guest address window, found with -d page), not qemu's own memory;
# their thread count leaves out qemu's own thread. Builds what it needs:
# RelWithDebInfo in build/ (x86_64) or build-ARCH/ (the cross presets) and the
# library alone at MinSizeRel in build-footprint-ARCH/. tools/cross-test.sh
# installs the cross packages (NCLINK_WITH_CROSS).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"

seconds=60
arches=()
while (($#)); do
  case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    x86_64 | x86-64 | amd64) arches+=(x86_64); shift ;;
    aarch64 | arm64) arches+=(aarch64); shift ;;
    armhf) arches+=(armhf); shift ;;
    *) echo "usage: bench/footprint.sh [--seconds N] [x86_64] [aarch64] [armhf]" >&2; exit 2 ;;
  esac
done
((${#arches[@]})) || arches=(x86_64 aarch64 armhf)
jobs=${NCLINK_JOBS:-$(nproc)}
warmup=$(( seconds >= 30 ? 10 : seconds / 3 ))

work=$(mktemp -d)
source tools/lib/local_broker.sh
trap 'stop_children; rm -rf "$work"' EXIT

# Options of the library split, when the tree has them (cmake -LH).
split_options() {
  local options
  options=$(cmake -N -LH "$1" 2>/dev/null || true)
  local extra=()
  if grep -q '^NCLINK_BUILD_PLANT:' <<<"$options"; then extra+=(-DNCLINK_BUILD_PLANT=OFF); fi
  if ((${#extra[@]})); then cmake "$1" "${extra[@]}" >/dev/null; fi
}

# sum_guest_rss PID LOG: KiB resident inside qemu's guest address window.
sum_guest_rss() {
  local pid=$1 log=$2 base size
  base=$(sed -n 's/^guest_base *\(0x[0-9a-f]*\).*/\1/p' "$log" | head -n 1)
  size=$(sed -n 's/.*reserved_va: base @ 0x[0-9a-f]* for \([0-9]*\) bytes.*/\1/p' "$log" | head -n 1)
  [[ -n $base ]] || { echo "?"; return; }
  size=${size:-4294967296}
  local lo=$((base)) hi=$((base + size)) kb=0 in=0 line start end
  while read -r line; do
    if [[ $line =~ ^([0-9a-f]+)-([0-9a-f]+)\  ]]; then
      start=$((16#${BASH_REMATCH[1]})) end=$((16#${BASH_REMATCH[2]}))
      in=$((start >= lo && end <= hi))
    elif ((in)) && [[ $line =~ ^Rss:\ +([0-9]+)\ kB ]]; then
      kb=$((kb + BASH_REMATCH[1]))
    fi
  done <"/proc/$pid/smaps"
  echo "$kb"
}

status_kb() { sed -n "s/^$2:[[:space:]]*\([0-9]*\) kB/\1/p" "/proc/$1/status"; }


measure() {
  local arch=$1 rel triplet qemu=() strip=strip toolchain="" preset
  case $arch in
    x86_64) rel=build preset=default triplet=x86_64-linux-gnu ;;
    aarch64) rel=build-aarch64 preset=cross-aarch64 triplet=aarch64-linux-gnu toolchain=cmake/toolchains/aarch64-linux-gnu.cmake
             # A fixed guest window (8 GiB) so the guest's pages can be told from qemu's.
             qemu=(qemu-aarch64 -R 0x200000000) strip=$triplet-strip ;;
    armhf) rel=build-armhf preset=cross-armhf triplet=arm-linux-gnueabihf toolchain=cmake/toolchains/arm-linux-gnueabihf.cmake
           qemu=(qemu-arm) strip=$triplet-strip ;;
  esac
  local small=build-footprint-$arch
  echo "footprint $arch: building (RelWithDebInfo in $rel/, MinSizeRel library in $small/)" >&2
  [[ -f $rel/CMakeCache.txt ]] || cmake --preset "$preset" >/dev/null
  # The build tree's other options stay as they are: libnclink.so is the
  # terminal library with or without the plant side beside it.
  cmake "$rel" -DNCLINK_BUILD_BENCH=ON >/dev/null
  cmake --build "$rel" -j "$jobs" --target nclink_shared nclink-sim bench_footprint >&2
  if [[ ! -f $small/CMakeCache.txt ]]; then
    cmake -S . -B "$small" -DCMAKE_BUILD_TYPE=MinSizeRel ${toolchain:+-DCMAKE_TOOLCHAIN_FILE=$toolchain} \
      -DNCLINK_BUILD_TESTS=OFF -DNCLINK_BUILD_BENCH=OFF -DNCLINK_BUILD_TOOLS=OFF -DNCLINK_BUILD_EXAMPLES=OFF >/dev/null
  fi
  split_options "$small"
  cmake --build "$small" -j "$jobs" --target nclink_shared >&2

  local lib_rel lib_small size_rel size_small needed
  lib_rel=$(readlink -f "$rel/lib/libnclink.so")
  lib_small=$(readlink -f "$small/lib/libnclink.so")
  "$strip" --strip-all -o "$work/rel.so" "$lib_rel"
  "$strip" --strip-all -o "$work/small.so" "$lib_small"
  size_rel=$(stat -c %s "$work/rel.so") size_small=$(stat -c %s "$work/small.so")
  needed=$(readelf -d "$lib_small" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | tr '\n' ' ')

  echo "footprint $arch: nclink-sim for ${seconds} s" >&2
  start_local_broker
  local log=$work/qemu-$arch.log sim_pid rss whole threads names
  if ((${#qemu[@]})); then
    "${qemu[@]}" -d page -D "$log" "$rel/bin/nclink-sim" --broker "$broker" --log-level warn >"$work/sim.log" 2>&1 &
  else
    "$rel/bin/nclink-sim" --broker "$broker" --log-level warn >"$work/sim.log" 2>&1 &
  fi
  sim_pid=$!
  pids+=("$sim_pid")
  sleep "$seconds"
  if ! kill -0 "$sim_pid" 2>/dev/null; then cat "$work/sim.log" >&2; echo "footprint $arch: nclink-sim died" >&2; return 1; fi
  whole=$(status_kb "$sim_pid" VmRSS)
  threads=$(ls "/proc/$sim_pid/task" | wc -l)
  if ((${#qemu[@]})); then
    rss=$(sum_guest_rss "$sim_pid" "$log")
    threads=$((threads - 1))  # qemu's own (RCU) thread
  else
    rss=$whole
  fi
  names=$(cat /proc/"$sim_pid"/task/*/comm | sort | uniq -c | awk '{printf "%s%s x%s", sep, $2, $1; sep=", "}')
  kill "$sim_pid"; wait "$sim_pid" 2>/dev/null || true

  echo "footprint $arch: bench_footprint for ${seconds} s (warm-up ${warmup} s)" >&2
  local out=$work/bench-$arch.txt
  "${qemu[@]}" "$rel/bin/bench_footprint" --seconds "$seconds" --warmup "$warmup" >"$out" 2>"$work/bench.err" ||
    { cat "$work/bench.err" >&2; echo "footprint $arch: bench_footprint failed" >&2; }
  kv() { sed -n "s/^$1=//p" "$out" | head -n 1; }
  local adapter_threads thread_names
  adapter_threads=$(kv adapter_threads)
  thread_names=$(sed -n 's/^thread=//p' "$out" | sort | uniq -c | awk '{printf "%s%s x%s", sep, $2, $1; sep=", "}')

  local mb_rel mb_small
  mb_rel=$(awk -v b="$size_rel" 'BEGIN{printf "%.2f", b/1048576}')
  mb_small=$(awk -v b="$size_small" 'BEGIN{printf "%.2f", b/1048576}')
  printf '\n### %s (%s)\n\n' "$arch" "$(if ((${#qemu[@]})); then echo "under ${qemu[*]}"; else echo native; fi)"
  printf '| what | measured | goal |\n|---|---|---|\n'
  printf '| libnclink.so stripped, RelWithDebInfo | %s MB (%s bytes) | |\n' "$mb_rel" "$size_rel"
  printf '| libnclink.so stripped, MinSizeRel | %s MB (%s bytes) | <= 1.5 MB (aarch64) |\n' "$mb_small" "$size_small"
  printf '| NEEDED | %s | |\n' "$needed"
  if ((${#qemu[@]})); then
    printf '| nclink-sim RSS after %s s | %s KiB (guest pages; qemu process %s KiB) | <= 8 MB |\n' "$seconds" "$rss" "$whole"
  else
    printf '| nclink-sim RSS after %s s | %s KiB | <= 8 MB |\n' "$seconds" "$rss"
  fi
  printf '| nclink-sim threads | %s (%s) | |\n' "$threads" "$names"
  printf '| threads the adapter starts | %s (%s) | <= 6 |\n' "$adapter_threads" "$thread_names"
  printf '| heap allocations per sample row (sampler thread) | %s (%s rows) | 0 |\n' "$(kv allocs_per_row)" "$(kv rows)"
  printf '| heap allocations per Sample DTU (whole process) | %s (%s DTUs) | <= 5 |\n' "$(kv allocs_per_dtu)" "$(kv dtus)"
  # The floor measured in the same run: a bare libmosquitto client.
  printf '| of which libmosquitto per message, QoS 1 / QoS 0 (floor) | %s / %s | |\n' \
    "$(kv mosquitto_allocs_per_message_qos1)" "$(kv mosquitto_allocs_per_message_qos0)"
  printf '| nclink'"'"'s own per Sample DTU (whole process less the QoS 1 floor) | %s | |\n' "$(kv nclink_allocs_per_dtu)"
  printf '| allocations by thread in %s s | %s | |\n' "$(kv window_s)" \
    "$(sed -n 's/^allocs_of=//p' "$out" | awk '{printf "%s%s %s", sep, $1, $2; sep=", "}')"
  # The broker of this architecture's run.
  stop_children
}

printf '# nclink footprint, %s, %s s per run (%s)\n' "$(date -u +%Y-%m-%d)" "$seconds" "$(git rev-parse --short HEAD 2>/dev/null || echo '?')"
for arch in "${arches[@]}"; do measure "$arch"; done
