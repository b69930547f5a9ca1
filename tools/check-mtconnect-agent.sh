#!/usr/bin/env bash
# Checks nclink-bridge against a real MTConnect agent (mtconnect/cppagent):
# the simulated mill on its own mosquitto, nclink-bridge following it, and
# the agent given the bridge's /probe as its Devices file and the bridge's
# SHDR port as its adapter, everything on 127.0.0.1. Then it compares the
# agent's /current with the bridge's, item by item (docs/bridge.md "Agents
# tried"), and changes one tool of the tool table through the bridge's
# GB/T 18759.6 data write to see the agent's value follow.
#
#   tools/check-mtconnect-agent.sh /path/to/cppagent/agent
#   MTCONNECT_AGENT=/path/to/agent tools/check-mtconnect-agent.sh
#
# NCLINK_BIN_DIR: where nclink-sim and nclink-bridge are (default build/bin).
# KEEP=1 keeps the scratch directory (logs, documents) and prints its path.
# Exit status: 0 every item agrees, 1 a difference (listed), 2 it could not run.
# Not part of the test suite: CI has no agent binary. It needs curl and python3.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"

agent=${1:-${MTCONNECT_AGENT:-}}
bin=${NCLINK_BIN_DIR:-build/bin}
if [[ -z $agent || ! -x $agent ]]; then
  echo "usage: tools/check-mtconnect-agent.sh AGENT_BINARY (or MTCONNECT_AGENT=...)" >&2
  exit 2
fi
for p in nclink-sim nclink-bridge; do
  [[ -x $bin/$p ]] || { echo "check-mtconnect-agent: $bin/$p not built (NCLINK_BIN_DIR)" >&2; exit 2; }
done
agent=$(cd "$(dirname "$agent")" && pwd)/$(basename "$agent")
bin=$(cd "$bin" && pwd)

work=$(mktemp -d)
source tools/lib/local_broker.sh
sim_pid=
cleanup() {
  if [[ -n $sim_pid ]]; then kill -CONT "$sim_pid" 2>/dev/null || true; fi
  stop_children
  if [[ -n ${KEEP:-} ]]; then echo "kept $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM
say() { printf '== %s\n' "$*"; }

start_local_broker || { echo "check-mtconnect-agent: no free loopback port" >&2; exit 2; }
dev=nclink-sim-mill-01
"$bin/nclink-sim" --broker "$broker" --model models/sim-mill.json --persistence "$work/sim-state" >"$work/sim.log" 2>&1 &
sim_pid=$!
pids+=($sim_pid)
http_port=$(free_port)
shdr_port=$(free_port $((http_port + 1)))
bridge="http://127.0.0.1:$http_port"
"$bin/nclink-bridge" --broker "$broker" --device "$dev" --http "127.0.0.1:$http_port" \
  --shdr "127.0.0.1:$shdr_port" >"$work/bridge.log" 2>&1 &
pids+=($!)

# The bridge is ready when the tool table (the last thing its first Query
# brings) has a value.
wait_for() {  # wait_for URL WHAT: until the document at URL has a Tool_table value
  local _
  for _ in $(seq 300); do
    if curl -sf "$1" 2>/dev/null | python3 -c 'import sys,re; d=sys.stdin.read(); sys.exit(0 if re.search(r"name=\"Tool_table\"[^>]*>\[", d) else 1)'; then
      return 0
    fi
    sleep 0.2
  done
  echo "check-mtconnect-agent: $2 never showed the tool table (logs in $work; KEEP=1 keeps them)" >&2
  return 1
}
wait_for "$bridge/current" "the bridge" || exit 2
curl -sf "$bridge/probe" >"$work/Devices.xml"
name=$(python3 -c 'import sys,re; print(re.search(r"<Device [^>]*name=\"([^\"]*)\"", open(sys.argv[1]).read()).group(1))' "$work/Devices.xml")

agent_port=$(free_port $((shdr_port + 1)))
agent_url="http://127.0.0.1:$agent_port"
# The agent's defaults otherwise (ConversionRequired, UpcaseDataItemValue,
# IgnoreTimestamps off): what a plant's agent.cfg has.
cat >"$work/agent.cfg" <<EOF
Devices = $work/Devices.xml
Port = $agent_port
ServerIp = 127.0.0.1
ReconnectInterval = 1000
PidFile = $work/agent.pid
Adapters {
  $name {
    Host = 127.0.0.1
    Port = $shdr_port
  }
}
logger_config {
  logging_level = info
  output = file $work/agent.log
}
EOF
(cd "$work" && exec "$agent" run "$work/agent.cfg") >"$work/agent.out" 2>&1 &
pids+=($!)
wait_for "$agent_url/current" "the agent" || exit 2
say "agent $(curl -sf "$agent_url/current" | python3 -c 'import sys,re; print(re.search(r"<Header [^>]*version=\"([^\"]*)\"", sys.stdin.read()).group(1))') at $agent_url, bridge at $bridge"

# compare BRIDGE_CURRENT AGENT_CURRENT DEVICES: every DataItem of DEVICES
# (the bridge's /probe), the same value in both. Numbers may differ in their
# last digits (the agent prints what it converted from nativeUnits with its
# own precision); conditions compare as their set of (state, nativeCode).
compare() {
  python3 - "$@" <<'PY'
import json, sys
import xml.etree.ElementTree as ET

def local(tag):
    return tag.split('}', 1)[-1]

def probe_items(path):
    items = {}
    for e in ET.parse(path).iter():
        if local(e.tag) == 'DataItem':
            items[e.get('id')] = e.attrib
    return items

def observations(path):
    out = {}
    for e in ET.parse(path).iter():
        i = e.get('dataItemId')
        if i is None:
            continue
        out.setdefault(i, []).append((local(e.tag), e.get('nativeCode') or '', (e.text or '').strip()))
    return out

def same(a, b):
    if a == b:
        return True
    try:
        x, y = float(a), float(b)
    except ValueError:
        return False
    return abs(x - y) <= 1e-9 * max(1.0, abs(y))

bridge_file, agent_file, devices = sys.argv[1:4]
items = probe_items(devices)
bridge, agent = observations(bridge_file), observations(agent_file)
differ, structured = [], []
for i, attrs in items.items():
    b, a = bridge.get(i), agent.get(i)
    if b is None or a is None:
        differ.append(f"{i}: bridge {b}, agent {a}")
        continue
    if attrs.get('category') == 'CONDITION':
        ok = sorted((s, c) for s, c, _ in b) == sorted((s, c) for s, c, _ in a)
    else:
        ok = len(b) == 1 and len(a) == 1 and same(a[0][2], b[0][2])
    if not ok:
        differ.append(f"{i} ({attrs.get('type')}): bridge {b[0][2][:80] if b else b!r} | agent {a[0][2][:80] if a else a!r}")
    if attrs.get('type') == 'MESSAGE' and (attrs.get('subType') or '').startswith('x:') and b[0][2].startswith(('[', '{')):
        try:
            equal = json.loads(a[0][2]) == json.loads(b[0][2])
        except ValueError:
            equal = False
        structured.append(f"{attrs.get('name')} {'JSON equal' if equal else 'DIFFERENT'} ({len(a[0][2])} characters)")
        if not equal and ok:
            differ.append(f"{i}: JSON differs")
print(f"items in /probe: {len(items)}; agree: {len(items) - len(differ)}; differ: {len(differ)}")
for s in structured:
    print(f"  list/dict item {s}")
for d in differ:
    print(f"  DIFFERENT {d}")
sys.exit(1 if differ else 0)
PY
}

# Hold the machine still (SIGSTOP of the simulator) so both sides have
# settled on the same last values, compare, let it go on; a difference must
# show in each of three tries to count.
status=1
for try in 1 2 3; do
  kill -STOP "$sim_pid"
  sleep 2
  curl -sf "$bridge/current" >"$work/bridge-current.xml"
  curl -sf "$agent_url/current" >"$work/agent-current.xml"
  kill -CONT "$sim_pid"
  say "comparison $try of /current"
  if compare "$work/bridge-current.xml" "$work/agent-current.xml" "$work/Devices.xml"; then status=0; break; fi
  sleep 2
done
[[ $status == 0 ]] || { echo "check-mtconnect-agent: the agent differs from the bridge" >&2; exit 1; }

# A Set through the bridge (GB/T 18759.6 data write) changing tool T01's
# length; the agent's tool table must follow.
tools_json=$(curl -sf "$bridge/current" | python3 -c '
import sys, json, xml.etree.ElementTree as ET
for e in ET.parse(sys.stdin).iter():
    if e.get("name") == "Tool_table":
        tools = json.loads(e.text)
        tools[0]["length"] = 123.456
        print(json.dumps(tools, separators=(",", ":")))')
body="<DataWriteRequest><Header version=\"1.0\" sendTime=\"$(date -u +%Y-%m-%dT%H:%M:%SZ)\" sender=\"check-mtconnect-agent\" operationId=\"1\" security=\"\"/><Operation command=\"SET\" description=\"tool T01 length\"><Value dataItemId=\"tools\">$(printf '%s' "$tools_json" | sed 's/&/\&amp;/g; s/</\&lt;/g; s/>/\&gt;/g')</Value></Operation></DataWriteRequest>"
code=$(curl -s -o "$work/write.xml" -w '%{http_code}' -X POST --data-binary "$body" -H 'Content-Type: application/xml' "$bridge/gbt18759/$dev/write")
if [[ $code != 200 ]]; then
  echo "check-mtconnect-agent: the bridge refused the tool table write (HTTP $code): $(head -c 400 "$work/write.xml")" >&2
  exit 1
fi
for _ in $(seq 50); do
  if curl -sf "$agent_url/current" | python3 -c '
import sys, json, xml.etree.ElementTree as ET
for e in ET.parse(sys.stdin).iter():
    if e.get("name") == "Tool_table":
        sys.exit(0 if json.loads(e.text)[0]["length"] == 123.456 else 1)
sys.exit(1)'; then
    say "tool table write through the bridge: the agent shows T01 length 123.456"
    exit 0
  fi
  sleep 0.2
done
echo "check-mtconnect-agent: the agent's tool table did not follow the write" >&2
exit 1
