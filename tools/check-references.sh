#!/usr/bin/env bash
# Checks that comments and docs cite only what a reader of the repository can
# follow: clauses of GB/T 41970 (and the other standards) and paths inside the
# repository, never working notes that live outside it (the design notes the
# project started from, seed file names, helper or issue numbers).
#   tools/check-references.sh [ROOT]    exit 0 when clean, 1 with one line per hit
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
# The pattern is assembled from pieces so this file does not match itself.
notes='WIRE|PERF-FLO''ORS|ARCHITECT''URE'
seeds='see''ds/'
pattern="(${notes})\\.md|${seeds}|seed 00[0-9]|\\bH[0-9]\\b|\\b[Ii]ssue ?#?[0-9]+\\b"
# The interop fixtures of the tests are a path CI provides beside the source
# tree (docs/mapping.md, "Tests"); naming that path is not a citation.
hits=$(grep -rnE "$pattern" src include tools tests docs bench examples drivers cmake \
         CMakeLists.txt README.md --exclude-dir=node_modules --exclude-dir=build \
         -I 2>/dev/null || true)
if [[ -n $hits ]]; then
  echo "$hits"
  echo "check-references: cite the standard's clause or a docs/ path instead (docs/architecture.md)" >&2
  exit 1
fi
echo "check-references: clean"
