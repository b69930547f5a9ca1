#!/usr/bin/env bash
# Installs what nclink needs to build, test and run, from Debian 12 packages.
# Idempotent: apt-get runs only when a package is missing.
set -euo pipefail

packages=(build-essential cmake pkg-config git
          nlohmann-json3-dev libfmt-dev libpaho-mqttpp-dev libpaho-mqtt-dev catch2
          mosquitto mosquitto-clients
          tmux lintian)
# tmux: the test of `nclink top` runs it in a real terminal. lintian: the
# packaging test lints the .deb files. (systemd-analyze, which the packaging
# test uses to verify the units, comes with Debian's systemd package.)
# clang is needed only for libFuzzer (tools/fuzz.sh).
if [[ "${NCLINK_WITH_CLANG:-0}" == 1 ]]; then packages+=(clang libclang-rt-14-dev); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
# Debian starts a system mosquitto on :1883 when installing it; nclink's tests
# start their own brokers on free ports and do not need it.
