#!/usr/bin/env bash
# The main job: a simulated 3-axis mill on NC-Link, talking to a local broker.
#   tools/demo.sh            # build, start mosquitto + nclink-sim, show NC-Link data, stop
#   tools/demo.sh --follow   # ... then keep printing the machine every second until Ctrl-C
# Installs what it needs (tools/install-deps.sh), builds into build/, and starts
# its own mosquitto on a free 127.0.0.1 port with the settings nclink ships
# for a plant's broker (tools/mosquitto/nclink.conf), so it never
# touches a broker already running on this machine.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
follow=0
[[ "${1:-}" == "--follow" ]] && follow=1

say() { printf '\n\033[1m== %s\033[0m\n' "$*"; }

tools/install-deps.sh
say "building nclink-sim, nclink-bridge and the nclink command-line tool"
cmake --preset default >/dev/null
cmake --build --preset default -j "$(nproc)" --target nclink-sim nclink_cli nclink_bridge_tool >/dev/null

work=$(mktemp -d)
source tools/lib/local_broker.sh
trap 'stop_children; rm -rf "$work"' EXIT
trap 'exit 130' INT TERM

# Its own broker on a free loopback port (NCLINK_DEMO_PORT to choose one).
start_local_broker "${NCLINK_DEMO_PORT:-$(free_port 18830)}" || { echo "demo: no free loopback port" >&2; exit 1; }
say "started mosquitto on $broker"
device=nclink-sim-mill-01
nclink() { build/bin/nclink "$1" --broker "$broker" --device "$device" "${@:2}"; }

say "starting the simulated mill (its log lines are marked [sim])"
# Process substitution, not a pipe: $! must be the simulator itself.
build/bin/nclink-sim --broker "$broker" --persistence "$work/state" > >(sed -u 's/^/  [sim] /') 2>&1 &
pids+=($!)
for _ in $(seq 50); do
  nclink state --timeout 500 2>/dev/null | grep -q online && break
  sleep 0.2
done

say "nclink state: the adapter's retained Notify/State"
nclink state

say "nclink probe: the machine's model (Probe/Query)"
nclink probe | head -n 45
echo "  ..."

say "nclink query: status, program and axis positions, three times a second apart"
for _ in 1 2 3; do
  nclink query status work_mode program line_number part_count x_position y_position z_position spindle_speed
  echo
  sleep 1
done

say "nclink set: feed override to 50 %, then read it back"
nclink set feed_override=50
nclink query feed_override feed_speed

say "lists and dicts: tool table length, tool 3, two parameters, coordinate system G54"
nclink query 'tools:{"operation":"get_length"}' 'tools:{"indexes":["3"]}' \
  'parameters:{"operation":"get_keys"}' 'coordinates:{"indexes":["0"]}' || true

say "errors are answered, never silent: unknown item, read-only item, bad index"
nclink query no_such_item || true
nclink set status='"free"' || true
nclink query 'tools:{"indexes":["999"]}' || true

say "samples: one Sample DTU of the slow channel (6.2.6), then a dynamic channel of two axes"
nclink watch --channel ch_slow --count 1 || true
nclink sample x_position y_position --sample-ms 10 --upload-ms 100 --count 5 || true

say "events: the program line changes (a change filter, 8.2.27)"
nclink events --count 2 line_number || true

say "methods: cycle start (Method/Call, Status, Result)"
nclink call cycle_start || true

say "nclink stats: the adapter's own counters and the sample channels' timing"
nclink stats || true

free_port() {
  local p
  for p in $(seq "$1" "$(($1 + 100))"); do
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null; then echo "$p"; return; fi
  done
}
say "MTConnect: nclink-bridge serves the mill over HTTP (GB/T 39561.3 appendix A)"
http_port=$(free_port 15000)
build/bin/nclink-bridge --broker "$broker" --device "$device" --http "127.0.0.1:$http_port" --shdr off \
  >"$work/bridge.log" 2>&1 &
pids+=($!)
bridge="http://127.0.0.1:$http_port"
for _ in $(seq 100); do
  curl -sf "$bridge/current" 2>/dev/null | grep -q 'Xact\|Position' && break
  sleep 0.2
done
echo "  \$ curl '$bridge/current?path=//Axes//DataItem[@type=\"POSITION\"]'"
curl -sf "$bridge/current?path=//Axes//DataItem%5B@type=%22POSITION%22%5D" \
  | grep -o '<Position[^>]*>[^<]*</Position>' | sed 's/^/  /' || echo "  (no answer: see $work/bridge.log)"

if [[ -x tools/nclink-opcua/nclink-opcua && -d tools/nclink-opcua/node_modules ]]; then
  say "OPC UA: nclink-opcua serves the same machine (GB/T 39561.3 appendix B); a client reads it"
  opc_port=$(free_port 14840)
  tools/nclink-opcua/nclink-opcua --bridge "$bridge" --port "$opc_port" --pki "$work/pki" >"$work/opcua.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 150); do grep -q "device $device: serving" "$work/opcua.log" 2>/dev/null && break; sleep 0.2; done
  echo "  \$ opcua-read.js opc.tcp://127.0.0.1:$opc_port $device feed_override x_position status"
  node tools/nclink-opcua/opcua-read.js "opc.tcp://127.0.0.1:$opc_port" "$device" feed_override x_position status \
    | sed 's/^/  /' || echo "  (see $work/opcua.log)"
fi

if ((follow)); then
  say "following the machine every second (Ctrl-C to stop)"
  while true; do
    nclink query status line_number x_position y_position z_position | tr '\n' ' '
    echo
    sleep 1
  done
fi
say "stopping (the simulator publishes its offline state)"
