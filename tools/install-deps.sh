#!/usr/bin/env bash
# Installs what nclink needs to build, test and run, from Debian 12 packages,
# and the OPC UA server's Node.js packages (tools/nclink-opcua) from npm.
# Idempotent: apt-get runs only when a package is missing, npm ci only when
# node_modules is missing or the lockfile changed since it ran.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

packages=(build-essential cmake pkg-config git
          nlohmann-json3-dev libfmt-dev libpaho-mqttpp-dev libpaho-mqtt-dev libmosquitto-dev catch2
          libssl-dev openssl
          mosquitto mosquitto-clients
          libcpp-httplib-dev libxml2-dev libxml2-utils curl libmodbus-dev abigail-tools
          tmux socat clang-format
          python3-dev pybind11-dev python3-pybind11 python3-pytest python3-mypy)
# libcpp-httplib-dev: the HTTP server of nclink-bridge and of the agent's
# dashboard and /metrics (src/http); libxml2-dev: the bridge's XPath
# (MTConnect path=); libxml2-utils: xmllint, which the bridge's tests validate
# MTConnect documents with. curl: the demo asks nclink-bridge for /current as
# a MTConnect client would. libmodbus-dev: the Modbus TCP driver
# (drivers/modbus) and its test PLC. tmux: the tests of `nclink top` and of the
# progress bar run the tool in a real terminal. socat: the Modbus RTU tests
# (tests/unit/modbus/test_modbus_rtu.cpp) join two pseudo-terminals with it,
# a serial cable with the driver on one end and simulated slaves on the other.
# libssl-dev: why a TLS connection failed (src/transport/tls_check.cpp);
# openssl: the TLS tests make their certificates with it.
# python3-dev, pybind11-dev, python3-pybind11: the Python package (python/,
# docs/python.md) is built with Debian's pybind11 2.10 for Debian's python3
# (3.11); python3-pytest runs its tests against nclink-sim, python3-mypy checks
# its type stubs.
# abigail-tools: abidw/abidiff for the ABI check against the last release (tools/check-abi.sh).
# clang-format (14 on Debian 12, the version .clang-format was tuned with):
# tools/check-format.sh checks the files a change touches.
# Heavier tools that only one test path needs (each test skips with a message
# when its tool is missing):
#   NCLINK_WITH_PACKAGING=1  lintian: the packaging test lints the .deb files
#     (systemd-analyze, which verifies the units, comes with Debian's systemd).
#   NCLINK_WITH_PROMETHEUS=1 prometheus: promtool checks the /metrics text.
#   NCLINK_WITH_PANDAS=1     python3-pandas (about 65 MB with numpy): the
#     DataFrame helper's test and the notebook example of the Python package.
#   NCLINK_WITH_BROWSER=1    chromium, chromium-driver, python3-selenium: the
#     dashboard's test in a real headless browser.
#   NCLINK_WITH_CROSS=1      cross compiler, qemu-user and the arm64 libraries
#     (tools/cross-test.sh; below).
#   NCLINK_WITH_RABBITMQ=1   rabbitmq-server (3.10, with its MQTT plugin; about
#     60 MB with Erlang): the cluster tests (tests/integration/cluster, label
#     `cluster`, docs/scaling.md) start a 3-node RabbitMQ cluster on loopback.
#     Opt-in because each of those tests boots a cluster (30-60 s on 2 cores)
#     and the whole suite must stay within its time; without it they skip.
#     The system RabbitMQ Debian may start (5672, epmd 4369) is left alone:
#     the tests' nodes have their own ports, epmd and cookie.
#   NCLINK_WITH_EJABBERD=1   ejabberd (23.01, its mod_mqtt; about 25 MB besides
#     Erlang): the ejabberd cluster tests (tests/integration/cluster, label
#     `cluster`, docs/scaling.md) start a 3-node ejabberd cluster on loopback
#     (about 6 s on an idle 2-core box); without ejabberd they skip. Debian
#     enables a system ejabberd (XMPP on 5222, MQTT on 1883), which a
#     container's policy may keep from starting; the tests never use it (own
#     ports, epmd, cookie and spool): `systemctl disable --now ejabberd` if it
#     is not wanted.
if [[ "${NCLINK_WITH_PACKAGING:-0}" == 1 ]]; then packages+=(lintian); fi
if [[ "${NCLINK_WITH_PROMETHEUS:-0}" == 1 ]]; then packages+=(prometheus); fi
if [[ "${NCLINK_WITH_PANDAS:-0}" == 1 ]]; then packages+=(python3-pandas); fi
if [[ "${NCLINK_WITH_BROWSER:-0}" == 1 ]]; then packages+=(chromium chromium-driver python3-selenium); fi
if [[ "${NCLINK_WITH_RABBITMQ:-0}" == 1 ]]; then packages+=(rabbitmq-server); fi
if [[ "${NCLINK_WITH_EJABBERD:-0}" == 1 ]]; then packages+=(ejabberd); fi
# clang is needed only for libFuzzer (tools/fuzz.sh).
if [[ "${NCLINK_WITH_CLANG:-0}" == 1 ]]; then packages+=(clang libclang-rt-14-dev); fi
# Node.js for nclink-opcua: the machine's own when it has one (any >= 18, e.g.
# NodeSource's 20), else Debian's nodejs/npm (18 on Debian 12, which
# node-opcua 2.182.2 supports). NCLINK_WITH_OPCUA=0 leaves it out.
if [[ "${NCLINK_WITH_OPCUA:-1}" == 1 ]] && ! command -v node >/dev/null 2>&1; then packages+=(nodejs npm); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all packages present"
else
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  # Debian starts a system mosquitto on :1883 when installing it; nclink's tests
  # start their own brokers on free ports and do not need it.
fi

# Cross builds (tools/cross-test.sh, docs/building.md "Cross-building"), only
# when asked: NCLINK_WITH_CROSS=1 (arm64, the CI leg) or a list of Debian
# architectures, e.g. NCLINK_WITH_CROSS="arm64 armhf". Each brings Debian's
# cross compiler (crossbuild-essential-ARCH, with its recommends: the cross C
# library), qemu-user to run the programs, and the libraries the build
# finds as multiarch -dev:ARCH packages beside the host's. apt upgrades a
# library's amd64 twin to the same version with it (multiarch needs equal
# versions), e.g. libssl-dev.
cross=${NCLINK_WITH_CROSS:-0}
if [[ "$cross" == 1 ]]; then cross=arm64; fi
if [[ "$cross" != 0 && -n "$cross" ]]; then
  sudo=""
  if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  cross_missing=()
  added=0
  for arch in ${cross//,/ }; do
    case "$arch" in
      arm64 | armhf) ;;
      *) echo "install-deps: NCLINK_WITH_CROSS: unknown architecture '$arch' (arm64, armhf)" >&2; exit 1 ;;
    esac
    if [[ "$arch" != "$(dpkg --print-architecture)" ]] && ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
      $sudo dpkg --add-architecture "$arch"
      added=1
    fi
    for p in crossbuild-essential-"$arch" qemu-user; do
      dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || cross_missing+=("$p")
    done
    for p in libfmt-dev libpaho-mqttpp-dev libpaho-mqtt-dev libmosquitto-dev libssl-dev libcpp-httplib-dev libxml2-dev; do
      dpkg-query -W -f='${Status}' "$p:$arch" 2>/dev/null | grep -q 'install ok installed' || cross_missing+=("$p:$arch")
    done
  done
  if ((${#cross_missing[@]} == 0)); then
    echo "install-deps: cross packages present ($cross)"
  else
    echo "install-deps: installing ${cross_missing[*]}"
    if ((added)) || [[ ${#missing[@]} -eq 0 ]]; then $sudo apt-get update -qq; fi
    # --no-remove: a conflict must stop here, never uninstall the host's packages.
    $sudo apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-remove "${cross_missing[@]}"
  fi
fi

# node-opcua for tools/nclink-opcua, exactly as package-lock.json pins it.
# The stamp holds the lockfile's hash at the last successful npm ci.
if [[ "${NCLINK_WITH_OPCUA:-1}" == 1 ]]; then
  opcua="$here/nclink-opcua"
  stamp="$opcua/node_modules/.nclink-lock.sha256"
  want=$(sha256sum "$opcua/package-lock.json" | cut -d' ' -f1)
  if [[ -d "$opcua/node_modules" && -f "$stamp" && "$(cat "$stamp")" == "$want" ]]; then
    echo "install-deps: node-opcua present (tools/nclink-opcua/node_modules)"
  else
    node_major=$(node -p 'process.versions.node.split(".")[0]')
    if ((node_major < 18)); then
      echo "install-deps: Node.js $(node --version) is too old for node-opcua 2.182.2 (needs >= 18)" >&2
      exit 1
    fi
    echo "install-deps: npm ci in tools/nclink-opcua (node $(node --version))"
    (cd "$opcua" && npm ci --engine-strict --no-audit --no-fund --omit=dev)
    echo "$want" > "$stamp"
  fi
fi
