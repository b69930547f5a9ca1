#!/usr/bin/env bash
# Builds nclink and runs the whole test suite (unit, fuzz smoke, consumer and,
# as they land, integration tests against a real mosquitto on loopback).
#   tools/run-tests.sh            # RelWithDebInfo build in build/
#   NCLINK_PRESET=asan tools/run-tests.sh   # ASan+UBSan build in build-asan/
#   NCLINK_FORMAT_BASE=origin/main tools/run-tests.sh
#       # checks the format of only the C/C++ files changed against that base
#       # (default: every C/C++ file, tools/check-format.sh --all)
#   NCLINK_WITH_CROSS=0 tools/run-tests.sh  # without the aarch64 leg
# After the native suite, the cross leg (tools/cross-test.sh aarch64): the
# terminal library and its unit tests built for 64-bit ARM and run under
# qemu-user, and nclink-sim for ARM serving a native client through a native
# mosquitto. armhf is run by hand (docs/building.md, "Cross-building").
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
# The whole suite: the dashboard in a real browser, /metrics through
# promtool, the .deb packages through lintian, the Python package's DataFrame
# helper with pandas (set a variable to 0 to skip
# that path on a machine without room for it).
export NCLINK_WITH_BROWSER=${NCLINK_WITH_BROWSER:-1}
export NCLINK_WITH_PROMETHEUS=${NCLINK_WITH_PROMETHEUS:-1}
export NCLINK_WITH_PACKAGING=${NCLINK_WITH_PACKAGING:-1}
export NCLINK_WITH_PANDAS=${NCLINK_WITH_PANDAS:-1}
tools/install-deps.sh

# Formatting first: a failure here costs seconds, not a build. The whole
# tree (it is formatted), or what a change touches against a base.
tools/check-format.sh "${NCLINK_FORMAT_BASE:---all}"

preset=${NCLINK_PRESET:-default}
jobs=${NCLINK_JOBS:-$(nproc)}
cmake --preset "$preset"
cmake --build --preset "$preset" -j "$jobs"
ctest --preset "$preset" -j "$jobs"

# The cross leg runs after the default (native) suite only; a sanitizer
# preset is about the native build.
# A cold leg costs about a third of the whole run (docs/building.md,
# "Cross-building", "Time"); armhf would cost as much again, so it is run by hand.
if [[ "${NCLINK_WITH_CROSS:-1}" != 0 && "$preset" == default ]]; then
  if tools/cross-test.sh aarch64; then
    echo "run-tests: cross leg aarch64 PASSED"
  else
    echo "run-tests: cross leg aarch64 FAILED" >&2
    exit 1
  fi
else
  echo "run-tests: cross leg not run (NCLINK_WITH_CROSS=0, or preset $preset)"
fi
