#!/usr/bin/env bash
# The main job: builds nclink and shows it working on the models it ships.
# (The simulated machine talking to a local broker joins this script with the
# adapter runtime; until then it validates every shipped model file and prints
# the problems a vendor would see.)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
tools/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default -j "$(nproc)" --target nclink_cli
for model in models/*.json; do
  echo "== nclink validate $model"
  build/bin/nclink validate "$model" || true
done
