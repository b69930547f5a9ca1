# Sourced by the scripts that run their own mosquitto on loopback
# (tools/demo.sh, tools/cross-test.sh, bench/footprint.sh): a free port, the
# broker with the settings nclink ships for a plant (tools/mosquitto/nclink.conf),
# and the children stopped in reverse order on exit. Run from the source tree.
# The caller sets `work` (a scratch directory, removed on exit) first.
pids=()

# free_port [FIRST]: the first loopback port from FIRST (default: random
# in 20000-39999) on which nothing answers; empty when none of 200 is free.
free_port() {
  local first=${1:-$((20000 + RANDOM % 20000))} candidate
  for candidate in $(seq "$first" $((first + 200))); do
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$candidate") 2>/dev/null; then echo "$candidate"; return; fi
  done
}

# start_local_broker [PORT]: mosquitto on 127.0.0.1 (on PORT, else a free
# one), no persistence; sets `port` and `broker` (tcp://...) and waits until
# it accepts connections. Returns 1 when no port is free.
start_local_broker() {
  port=${1:-$(free_port)}
  [[ -n $port ]] || return 1
  broker="tcp://127.0.0.1:$port"
  {
    echo "listener $port 127.0.0.1"
    echo "allow_anonymous true"
    echo "persistence false"
    cat tools/mosquitto/nclink.conf  # set_tcp_nodelay true, ...
  } >"$work/mosquitto.conf"
  "$(command -v mosquitto || echo /usr/sbin/mosquitto)" -c "$work/mosquitto.conf" >"$work/mosquitto.log" 2>&1 &
  pids+=($!)
  local _
  for _ in $(seq 100); do (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && return 0; sleep 0.1; done
}

# Reverse start order: a program publishes its offline state while the
# broker is still there.
stop_children() {
  local i
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[i]}" 2>/dev/null || true
    wait "${pids[i]}" 2>/dev/null || true
  done
  pids=()
}
