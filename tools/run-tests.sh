#!/usr/bin/env bash
# Builds nclink and runs the whole test suite (unit, fuzz smoke, consumer and,
# as they land, integration tests against a real mosquitto on loopback).
#   tools/run-tests.sh            # RelWithDebInfo build in build/
#   NCLINK_PRESET=asan tools/run-tests.sh   # ASan+UBSan build in build-asan/
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
tools/install-deps.sh

preset=${NCLINK_PRESET:-default}
jobs=${NCLINK_JOBS:-$(nproc)}
cmake --preset "$preset"
cmake --build --preset "$preset" -j "$jobs"
ctest --preset "$preset" -j "$jobs"
