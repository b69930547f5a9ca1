#!/usr/bin/env bash
# Checks with clang-format (.clang-format at the top of the tree) the C and
# C++ files of the tree, or those that differ from a base.
#   tools/check-format.sh --all        every C/C++ file in git (and new ones)
#   tools/check-format.sh BASE         e.g. main, origin/main, a commit: only
#                                      what a change touches
#   tools/check-format.sh --fix ...    rewrite those files in place instead
# Exit 0 when every file checked is formatted, 1 naming each file that is not
# (with the diff clang-format wants), 2 for usage or a missing clang-format.
# The whole tree is formatted (one commit of its own), so CI checks it all:
# tools/run-tests.sh runs `--all` first, or `BASE` when NCLINK_FORMAT_BASE
# names one (docs/building.md, "Format"). A few seconds for ~780 files.
set -euo pipefail

fix=0
if [[ ${1:-} == --fix ]]; then
  fix=1
  shift
fi
if [[ $# -ne 1 ]]; then
  sed -n '2,13p' "$0" >&2
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
if [[ $base != --all ]] && ! git rev-parse --verify --quiet "$base^{commit}" >/dev/null; then
  echo "check-format: '$base' is not a commit" >&2
  exit 2
fi

# Added, copied, modified or renamed since the base, working tree included,
# and new files not yet added to git; deleted files have nothing to check.
patterns=('*.c' '*.h' '*.cc' '*.cpp' '*.hpp')
if [[ $base == --all ]]; then
  listed=(git ls-files --cached -- "${patterns[@]}")
  what="in the tree"
else
  listed=(git diff --name-only --diff-filter=ACMR "$base" -- "${patterns[@]}")
  what="changed against $base"
fi
mapfile -t files < <({ "${listed[@]}"
                       git ls-files --others --exclude-standard -- "${patterns[@]}"; } |
                     grep -v '/node_modules/' | sort -u |
                     while read -r f; do [[ -f $f ]] && echo "$f"; done || true)
if ((${#files[@]} == 0)); then
  echo "check-format: no C or C++ file $what"
  exit 0
fi

if ((fix)); then
  "$formatter" -i --style=file "${files[@]}"
  echo "check-format: formatted ${#files[@]} file(s) $what"
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
  echo "check-format: $bad of ${#files[@]} file(s) $what not formatted (tools/check-format.sh --fix $base)" >&2
  exit 1
fi
echo "check-format: ${#files[@]} file(s) $what formatted"
