#!/usr/bin/env bash
# The Debian packages, end to end, without touching this machine: builds them
# (cpack -G DEB), unpacks them into a scratch root (dpkg -x), and checks what a
# plant's IT relies on: package fields, pkg-config and find_package against
# the unpacked tree, the installed programs, the systemd units
# (systemd-analyze verify), the maintainer scripts run twice (with stand-ins
# for the commands that would change the machine), and lintian.
#   packaging_test.sh BUILD_DIR SOURCE_DIR WORK_DIR CXX
set -euo pipefail
build=$1 source=$2 work=$3 cxx=$4
rm -rf "$work"
mkdir -p "$work"
root=$work/root
fail() { echo "packaging test: $*" >&2; exit 1; }
step() { echo "--- $* ($SECONDS s)"; }

step "cpack -G DEB"
(cd "$work" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/packages" >"$work/cpack.log" 2>&1) ||
  { cat "$work/cpack.log"; fail "cpack failed"; }
version=$(sed -n 's/^set(CPACK_PACKAGE_VERSION "\(.*\)")$/\1/p' "$build/CPackConfig.cmake")
release=$(sed -n 's/^set(CPACK_DEBIAN_PACKAGE_RELEASE "\(.*\)")$/\1/p' "$build/CPackConfig.cmake")
soversion=${version%%.*}
arch=$(dpkg --print-architecture)
declare -A deb
for p in "libnclink$soversion" libnclink-dev "libnclink-plant$soversion" libnclink-plant-dev nclink-tools nclink-agent nclink-bridge; do
  deb[$p]=$work/packages/${p}_${version}-${release}_${arch}.deb
  [[ -f ${deb[$p]} ]] || { ls "$work/packages"; fail "no package ${deb[$p]##*/}"; }
done
# The driver packages, when the build has their plugins (libmodbus found; the
# bridge's libxml2 and cpp-httplib for MTConnect).
declare -A driver_lib=([modbus]=libmodbus5 [mtconnect]=libxml2)
drivers=()
for d in modbus mtconnect; do
  [[ -f $build/lib/nclink-$d.so ]] || continue
  drivers+=("$d")
  deb[nclink-driver-$d]=$work/packages/nclink-driver-${d}_${version}-${release}_${arch}.deb
  [[ -f ${deb[nclink-driver-$d]} ]] || { ls "$work/packages"; fail "no package nclink-driver-$d for lib/nclink-$d.so"; }
done

# The Python package, when the build has the extension module (docs/python.md).
with_python=0
if compgen -G "$build/python/nclink/_nclink*.so" >/dev/null; then
  with_python=1
  deb[python3-nclink]=$work/packages/python3-nclink_${version}-${release}_${arch}.deb
  [[ -f ${deb[python3-nclink]} ]] || { ls "$work/packages"; fail "no package python3-nclink for the built extension module"; }
fi

# lintian is the slowest part: it runs beside the other checks.
lint_pid=""
if command -v lintian >/dev/null; then
  # Overrides ship in the packages (packaging/lintian/), each with its reason.
  lintian --fail-on error,warning --tag-display-limit 0 "$work"/packages/*.deb >"$work/lintian.log" 2>&1 &
  lint_pid=$!
fi

step "package fields"
field() { dpkg-deb -f "${deb[$1]}" "$2"; }
for p in "${!deb[@]}"; do
  [[ $(field "$p" Version) == "$version-$release" ]] || fail "$p: Version $(field "$p" Version)"
done
[[ $(field libnclink-dev Depends) == *"libnclink$soversion (= $version-$release)"* ]] || fail "libnclink-dev: Depends $(field libnclink-dev Depends)"
# The two libraries (docs/building.md): the terminal one needs no paho, the
# plant one needs the terminal one.
[[ $(field libnclink-dev Depends) != *paho* ]] || fail "libnclink-dev: Depends $(field libnclink-dev Depends)"
[[ $(field "libnclink$soversion" Depends) != *paho* ]] || fail "libnclink$soversion: Depends $(field "libnclink$soversion" Depends)"
[[ $(field libnclink-plant-dev Depends) == *"libnclink-plant$soversion (= $version-$release)"* &&
   $(field libnclink-plant-dev Depends) == *"libnclink-dev (= $version-$release)"* ]] ||
  fail "libnclink-plant-dev: Depends $(field libnclink-plant-dev Depends)"
[[ $(field "libnclink-plant$soversion" Depends) == *"libnclink$soversion"* && $(field "libnclink-plant$soversion" Depends) == *libpaho-mqttpp3* ]] ||
  fail "libnclink-plant$soversion: Depends $(field "libnclink-plant$soversion" Depends)"
dpkg-deb -c "${deb[libnclink-dev]}" | grep -E "include/nclink/(client|agent|mapping|paho_transport)\.hpp" && fail "libnclink-dev ships plant headers"
dpkg-deb -c "${deb[libnclink-plant-dev]}" | grep "include/nclink/client.hpp" >/dev/null || fail "libnclink-plant-dev: no client.hpp"
# dpkg-shlibdeps found what the programs link.
[[ $(field nclink-tools Depends) == *libpaho-mqttpp3* ]] || fail "nclink-tools: Depends $(field nclink-tools Depends)"
[[ $(field nclink-agent Depends) == *adduser* && $(field nclink-agent Depends) == *libc6* ]] || fail "nclink-agent: Depends $(field nclink-agent Depends)"
dpkg-deb --ctrl-tarfile "${deb[nclink-agent]}" | tar -xO ./conffiles | grep -x >/dev/null /etc/nclink/agent.json ||
  fail "nclink-agent: /etc/nclink/agent.json is not a conffile"
dpkg-deb --ctrl-tarfile "${deb[nclink-bridge]}" | tar -xO ./conffiles | grep -x >/dev/null /etc/nclink/bridge.json ||
  fail "nclink-bridge: /etc/nclink/bridge.json is not a conffile"
[[ $(field nclink-bridge Depends) == *libcpp-httplib* ]] || fail "nclink-bridge: Depends $(field nclink-bridge Depends)"
# dpkg-shlibdeps found each driver's protocol library; nothing of nclink's
# own (the plugin carries its static copy).
for d in "${drivers[@]}"; do
  dep=$(field "nclink-driver-$d" Depends)
  [[ $dep == *"${driver_lib[$d]}"* && $dep != *libnclink* ]] || fail "nclink-driver-$d: Depends $dep"
done
dpkg-deb --ctrl-tarfile "${deb[libnclink$soversion]}" | tar -xO ./shlibs | grep "^libnclink $soversion libnclink$soversion" >/dev/null ||
  fail "libnclink$soversion: no shlibs"
dpkg-deb --ctrl-tarfile "${deb[libnclink-plant$soversion]}" | tar -xO ./shlibs | grep "^libnclink-plant $soversion libnclink-plant$soversion" >/dev/null ||
  fail "libnclink-plant$soversion: no shlibs"

step "dpkg -x into $root"
for p in "${!deb[@]}"; do dpkg -x "${deb[$p]}" "$root"; done
for f in usr/bin/nclink usr/bin/nclink-conform usr/bin/nclink-sim usr/bin/nclink-agent etc/nclink/agent.json \
         lib/systemd/system/nclink-agent.service usr/lib/sysusers.d/nclink-agent.conf \
         usr/bin/nclink-bridge etc/nclink/bridge.json lib/systemd/system/nclink-bridge.service \
         usr/lib/sysusers.d/nclink-bridge.conf \
         usr/share/nclink/models/sim-mill.json usr/share/nclink/schema/agent.schema.json \
         usr/include/nclink/adapter.hpp; do
  [[ -e $root/$f ]] || fail "not installed: /$f"
done
[[ -n $(find "$root" -name 'libnclink.so.*' -print -quit) ]] || fail "no libnclink.so.*"
[[ -n $(find "$root" -name 'libnclink-plant.so.*' -print -quit) ]] || fail "no libnclink-plant.so.*"
[[ -n $(find "$root" -path '*/nclink/drivers/nclink-sim.so' -print -quit) ]] || fail "no sim plugin"
# Each driver plugin is where nclink looks for plugins, and its entry point is
# the only function it exports (its static nclink stays local).
for d in "${drivers[@]}"; do
  plugin=$(find "$root" -path "*/nclink/drivers/nclink-$d.so" -print -quit)
  [[ -n $plugin ]] || fail "nclink-driver-$d: no nclink/drivers/nclink-$d.so"
  exports=$(nm -D --defined-only "$plugin" | awk '$2 == "T" {print $3}' | sort -u)
  [[ $exports == nclink_driver_entry ]] || fail "nclink-$d.so exports: $(echo $exports)"
done
# python3-nclink: Debian's python3 (the extension is built for 3.11), the
# package where Debian's python3 looks, importable from the unpacked tree and
# answering from its compiled half (a failed request raises the table-19 class).
if ((with_python)); then
  [[ $(field python3-nclink Depends) == *"python3 (>= 3.11)"* ]] || fail "python3-nclink: Depends $(field python3-nclink Depends)"
  [[ -f $root/usr/lib/python3/dist-packages/nclink/__init__.py ]] || fail "python3-nclink: no nclink/__init__.py in /usr/lib/python3/dist-packages"
  PYTHONPATH=$root/usr/lib/python3/dist-packages /usr/bin/python3 -c '
import nclink, sys
assert nclink.__file__.startswith(sys.argv[1]), nclink.__file__
c = nclink.Client("tcp://127.0.0.1:1")
try:
    c.get("dev", "status")
except nclink.Unavailable:
    pass
else:
    raise SystemExit("a request before connect() did not raise nclink.Unavailable")
finally:
    c.close()
' "$root" || fail "python3-nclink: import nclink from the unpacked package failed"
fi
pcdir=$(dirname "$(find "$root" -name nclink.pc -print -quit)")
libdir=$(dirname "$pcdir")

step "pkg-config against the unpacked tree"
# nclink.pc is relocatable (its prefix is found from where the file is), so
# no PKG_CONFIG_SYSROOT_DIR is needed: the paths lead into the unpacked tree.
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs nclink)
includes="" libs=""
for f in $flags; do
  case $f in
    -I*) includes+=" $(realpath -m "${f#-I}")" ;;
    -L*) libs+=" $(realpath -m "${f#-L}")" ;;
  esac
done
[[ $includes == *" $root/usr/include"* && $libs == *" $(realpath "$libdir")"* && $flags == *-lnclink* ]] ||
  fail "pkg-config: $flags"
# shellcheck disable=SC2086
"$cxx" -std=c++17 "$source/tests/consumer/project/main.cpp" -o "$work/pc_consumer" $flags -Wl,-rpath,"$libdir"
[[ $("$work/pc_consumer") == *"Node not exists"* ]] || fail "pkg-config consumer"
# (no grep -q after a pipe: with pipefail, its early exit would fail the writer)
# (nclink.pc's run path may name the directory unnormalized: compare real paths)
used=$(ldd "$work/pc_consumer" | awk '$1 ~ /^libnclink\.so/ {print $3}')
[[ -n $used && $(realpath "$(dirname "$used")") == "$(realpath "$libdir")" ]] ||
  fail "pkg-config consumer does not use the packaged library (it uses ${used:-none})"

step "find_package against the unpacked tree"
cmake -S "$source/tests/consumer/project" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$root/usr" \
      -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_RPATH="$libdir" >"$work/consumer.log" 2>&1 ||
  { cat "$work/consumer.log"; fail "consumer configure"; }
cmake --build "$work/consumer" >>"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; fail "consumer build"; }
[[ $("$work/consumer/nclink_consumer") == *"Node not exists"* ]] || fail "find_package consumer"

step "the installed programs"
[[ $("$root/usr/bin/nclink" --version) == "nclink $version" ]] || fail "nclink --version: $("$root/usr/bin/nclink" --version)"
"$root/usr/bin/nclink-agent" --config "$root/etc/nclink/agent.json" --check-config >/dev/null ||
  fail "the shipped /etc/nclink/agent.json is refused"
"$root/usr/bin/nclink" config check --kind agent "$root/etc/nclink/agent.json" >/dev/null || fail "nclink config check of agent.json"
"$root/usr/bin/nclink-bridge" --help | grep dashboard >/dev/null || fail "nclink-bridge --help"
# nclink-sim finds the packaged model relative to itself.
"$root/usr/bin/nclink-sim" --broker tcp://127.0.0.1:9 --log-level info >/dev/null 2>"$work/sim.log" &
sim=$!
for _ in $(seq 50); do grep -q simulating "$work/sim.log" && break; sleep 0.1; done
kill "$sim" 2>/dev/null || true
wait "$sim" 2>/dev/null || true
grep -q "simulating $root/usr/share/nclink/models/sim-mill.json" "$work/sim.log" || { cat "$work/sim.log"; fail "nclink-sim: packaged model"; }

step "systemd units"
if command -v systemd-analyze >/dev/null; then
  mkdir -p "$work/units"
  for unit in "$root"/lib/systemd/system/*.service; do
    # A copy whose programs point into the unpacked tree: verify checks that
    # they exist and are executable. Any output (an unknown key, a bad
    # value) fails the test.
    copy=$work/units/${unit##*/}
    sed "s|/usr/bin/|$root/usr/bin/|g" "$unit" >"$copy"
    out=$(systemd-analyze verify "$copy" 2>&1) || { echo "$out"; fail "systemd-analyze verify ${unit##*/}"; }
    [[ -z $out ]] || { echo "$out"; fail "systemd-analyze verify ${unit##*/} warns"; }
    # The agent and the bridge reload on SIGHUP.
    if [[ ${unit##*/} == nclink-agent.service || ${unit##*/} == nclink-bridge.service ]]; then
      grep -q '^ExecReload=/bin/kill -HUP \$MAINPID$' "$unit" || fail "${unit##*/}: no SIGHUP reload"
    fi
    if [[ ${unit##*/} == nclink-agent.service ]]; then
      grep -q '^ExecStart=.* --metrics 127.0.0.1:9470$' "$unit" || fail "${unit##*/}: no loopback /metrics"
    fi
    grep -q '^ProtectSystem=strict$' "$unit" && grep -q '^User=nclink$' "$unit" || fail "${unit##*/}: not hardened"
  done
else
  echo "systemd-analyze not installed (Debian package systemd): units not verified"
fi

step "maintainer scripts, twice"
stubs=$work/stubs dpkgroot=$work/dpkgroot
mkdir -p "$stubs" "$dpkgroot"
: >"$work/calls"
# Stand-ins that log their call and keep their state in the scratch directory.
for cmd in systemd-sysusers adduser deb-systemd-helper deb-systemd-invoke systemctl; do
  printf '#!/bin/sh\necho "%s $*" >>"%s"\n' "$cmd" "$work/calls" >"$stubs/$cmd"
done
cat >"$stubs/getent" <<STUB
#!/bin/sh
grep -q "^\$2\$" "$work/users" 2>/dev/null
STUB
cat >"$stubs/install" <<STUB
#!/bin/sh
echo "install \$*" >>"$work/calls"
for last; do :; done
mkdir -p "\$last"
STUB
cat >"$stubs/dpkg-statoverride" <<STUB
#!/bin/sh
echo "dpkg-statoverride \$*" >>"$work/calls"
case "\$1" in
  --list) grep -q " \$2\$" "$work/overrides" 2>/dev/null ;;
  --update) echo "\$3 \$4 \$5 \$6" >>"$work/overrides" ;;
  --remove) grep -v " \$2\$" "$work/overrides" >"$work/overrides.new" || true; mv "$work/overrides.new" "$work/overrides" ;;
esac
STUB
chmod +x "$stubs"/*
mkdir -p "$work/scripts"
dpkg-deb -e "${deb[nclink-agent]}" "$work/scripts"
run_script() { PATH="$stubs:$PATH" DPKG_ROOT=$dpkgroot sh -e "$work/scripts/$1" "${@:2}"; }
run_script postinst configure
first=$(wc -l <"$work/calls")
run_script postinst configure
grep -c "dpkg-statoverride --update --add root nclink 0640 /etc/nclink/agent.json" "$work/calls" | grep -x >/dev/null 1 ||
  fail "postinst twice: the permission override is added $(grep -c 'statoverride --update' "$work/calls") times"
[[ -d $dpkgroot/var/lib/nclink/agent ]] || fail "postinst: no state directory"
[[ $(grep -c "systemd-sysusers $dpkgroot/usr/lib/sysusers.d/nclink-agent.conf" "$work/calls") == 2 ]] ||
  fail "postinst: the user is not made from the sysusers.d file"
# An upgrade restarts a running service; a fresh install starts nothing.
if head -n "$first" "$work/calls" | grep "try-restart" >/dev/null; then fail "postinst: a fresh install restarted the service"; fi
run_script postinst configure "$version-0"
grep -q "deb-systemd-invoke try-restart nclink-agent.service" "$work/calls" || [[ ! -d /run/systemd/system ]] ||
  fail "postinst: an upgrade does not restart the service"
run_script prerm remove
run_script postrm remove
run_script postrm purge
[[ ! -e $dpkgroot/var/lib/nclink/agent ]] || fail "postrm purge: the state directory stays"
grep -q " /etc/nclink/agent.json" "$work/overrides" && fail "postrm purge: the permission override stays"
run_script postrm purge  # again: nothing left to do, no error

step "lintian"
if [[ -n $lint_pid ]]; then
  wait "$lint_pid" || { cat "$work/lintian.log"; fail "lintian"; }
  grep -v "root privileges" "$work/lintian.log" || true
else
  echo "lintian not installed: packages not linted (tools/install-deps.sh installs it)"
fi
step "done"
