#!/usr/bin/env bash
# Builds nclink and runs the whole test suite (unit, fuzz smoke, consumer and,
# as they land, integration tests against a real mosquitto on loopback).
#   tools/run-tests.sh            # RelWithDebInfo build in build/
#   NCLINK_PRESET=asan tools/run-tests.sh   # ASan+UBSan build in build-asan/
#   NCLINK_FORMAT_BASE=origin/main tools/run-tests.sh
#       # first checks the format of the C/C++ files changed against that base
#       # (tools/check-format.sh; CI sets it to the branch a change goes into)
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

# Formatting first, when CI knows the base a change goes into: a failure
# here costs seconds, not a build. Only the files the change touches.
if [[ -n "${NCLINK_FORMAT_BASE:-}" ]]; then
  tools/check-format.sh "$NCLINK_FORMAT_BASE"
fi

preset=${NCLINK_PRESET:-default}
jobs=${NCLINK_JOBS:-$(nproc)}
cmake --preset "$preset"
cmake --build --preset "$preset" -j "$jobs"
ctest --preset "$preset" -j "$jobs"
