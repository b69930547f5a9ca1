#!/usr/bin/env bash
# Runs a libFuzzer target (clang, ASan+UBSan) for a while.
#   tools/fuzz.sh probe 60     # fuzz the probe (model) parser for 60 s
#   tools/fuzz.sh dtu 300      # fuzz the DTU decoders for 5 minutes
# Targets are tests/fuzz/fuzz_<name>.cpp; the seed corpus is
# tests/fuzz/corpus/<name>/; new inputs libFuzzer finds go to
# build-fuzz/corpus/<name>/ (copy interesting ones into the seed corpus).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
name=${1:?usage: tools/fuzz.sh TARGET [SECONDS]   (targets: $(ls tests/fuzz/fuzz_*.cpp | sed 's|.*/fuzz_||; s|\.cpp||' | tr '\n' ' '))}
seconds=${2:-60}
NCLINK_WITH_CLANG=1 tools/install-deps.sh
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)" --target "fuzz_${name}"
mkdir -p "build-fuzz/corpus/${name}"
exec build-fuzz/bin/fuzz_${name} -max_total_time="${seconds}" -timeout=10 -rss_limit_mb=2048 \
  "build-fuzz/corpus/${name}" "tests/fuzz/corpus/${name}"
