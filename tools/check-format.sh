#!/usr/bin/env bash
# Checks with clang-format (.clang-format at the top of the tree) the C and
# C++ files that differ from a base: only what a change touches, so a branch
# is never asked to reformat files it did not edit.
#   tools/check-format.sh BASE         e.g. main, origin/main, a commit
#   tools/check-format.sh --fix BASE   rewrite those files in place instead
# Exit 0 when every changed file is formatted, 1 naming each file that is not
# (with the diff clang-format wants), 2 for usage or a missing clang-format.
# CI: tools/run-tests.sh runs it first when NCLINK_FORMAT_BASE names the base
# (docs/building.md, "Format").
set -euo pipefail

fix=0
if [[ ${1:-} == --fix ]]; then
  fix=1
  shift
fi
if [[ $# -ne 1 ]]; then
  sed -n '2,12p' "$0" >&2
  exit 2
fi
base=$1
root=$(git rev-parse --show-toplevel)
cd "$root"

# The formatter the tree was formatted with: Debian 12's clang-format 14.
# Another version formats a few constructs differently.
formatter=""
for candidate in clang-format-14 clang-format; do
  if command -v "$candidate" >/dev/null 2>&1; then
    formatter=$candidate
    break
  fi
done
if [[ -z $formatter ]]; then
  echo "check-format: clang-format not found (tools/install-deps.sh installs it)" >&2
  exit 2
fi
if ! git rev-parse --verify --quiet "$base^{commit}" >/dev/null; then
  echo "check-format: '$base' is not a commit" >&2
  exit 2
fi

# Added, copied, modified or renamed since the base, working tree included,
# and new files not yet added to git; deleted files have nothing to check.
patterns=('*.c' '*.h' '*.cc' '*.cpp' '*.hpp')
mapfile -t files < <({ git diff --name-only --diff-filter=ACMR "$base" -- "${patterns[@]}"
                       git ls-files --others --exclude-standard -- "${patterns[@]}"; } |
                     grep -v '/node_modules/' | sort -u || true)
if ((${#files[@]} == 0)); then
  echo "check-format: no C or C++ file changed against $base"
  exit 0
fi

if ((fix)); then
  "$formatter" -i --style=file "${files[@]}"
  echo "check-format: formatted ${#files[@]} file(s) changed against $base"
  exit 0
fi

bad=0
for f in "${files[@]}"; do
  if ! "$formatter" --dry-run --Werror --style=file "$f" >/dev/null 2>&1; then
    bad=$((bad + 1))
    echo "check-format: $f is not formatted; clang-format wants:"
    diff -u "$f" <("$formatter" --style=file "$f") | sed -e '1,2d' || true
  fi
done
if ((bad)); then
  echo "check-format: $bad of ${#files[@]} changed file(s) not formatted (tools/check-format.sh --fix $base)" >&2
  exit 1
fi
echo "check-format: ${#files[@]} changed file(s) formatted"
