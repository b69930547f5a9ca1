#!/usr/bin/env bash
# tools/check-format.sh checks the files changed against a base and only
# those: in a scratch repository with the project's .clang-format, a badly
# formatted file that the change does not touch passes, a badly formatted
# changed file fails and is named, --fix formats it, and then the check passes.
# --all (what CI runs) checks every file, the untouched one included, and
# --fix --all formats them all.
#   check_format_test.sh SOURCE WORK
set -euo pipefail
source_dir=$1
work=$2
if ! command -v clang-format-14 >/dev/null 2>&1 && ! command -v clang-format >/dev/null 2>&1; then
  echo "clang-format not installed: skipped (tools/install-deps.sh installs it)"
  exit 0
fi
rm -rf "$work"
mkdir -p "$work/tools"
cd "$work"
git init -q .
git config user.email test@example.invalid
git config user.name test
cp "$source_dir/.clang-format" .
cp "$source_dir/tools/check-format.sh" tools/
printf 'int   untouched( int a ){return a;}\n' > untouched.cpp
git add -A
git commit -q -m base
base=$(git rev-parse HEAD)

fail() { echo "FAIL: $*"; exit 1; }

out=$(tools/check-format.sh "$base") || fail "nothing changed, yet the check failed: $out"

printf 'int   changed( int a ){return a;}\n' > changed.cpp
set +e
out=$(tools/check-format.sh "$base" 2>&1)
rc=$?
set -e
[[ $rc -eq 1 ]] || fail "a badly formatted changed file passed (exit $rc): $out"
grep -q 'changed.cpp is not formatted' <<<"$out" || fail "the changed file is not named: $out"
if grep -q 'untouched.cpp' <<<"$out"; then fail "a file the change did not touch was checked: $out"; fi

tools/check-format.sh --fix "$base" >/dev/null
grep -q 'int changed(int a) { return a; }' changed.cpp || fail "--fix did not format: $(cat changed.cpp)"
grep -q 'int   untouched' untouched.cpp || fail "--fix touched a file outside the change"
out=$(tools/check-format.sh "$base") || fail "formatted, yet the check failed: $out"

set +e
out=$(tools/check-format.sh --all 2>&1)
rc=$?
set -e
[[ $rc -eq 1 ]] || fail "--all passed a badly formatted file the change did not touch (exit $rc): $out"
grep -q 'untouched.cpp is not formatted' <<<"$out" || fail "--all did not name the untouched file: $out"
if grep -q 'changed.cpp is not' <<<"$out"; then fail "--all named a formatted file: $out"; fi
git rm -q --cached untouched.cpp && printf 'int   deleted_later( );\n' > gone.cpp && git add gone.cpp && rm gone.cpp
tools/check-format.sh --fix --all >/dev/null
grep -q 'int untouched(int a) { return a; }' untouched.cpp || fail "--fix --all did not format an untracked file: $(cat untouched.cpp)"
out=$(tools/check-format.sh --all) || fail "all formatted (a deleted file in the index), yet --all failed: $out"

set +e
tools/check-format.sh >/dev/null 2>&1; rc_usage=$?
tools/check-format.sh no-such-base >/dev/null 2>&1; rc_base=$?
set -e
[[ $rc_usage -eq 2 && $rc_base -eq 2 ]] || fail "usage errors exit $rc_usage and $rc_base, not 2"
echo "check-format: only changed files checked (all with --all), named when unformatted, fixed by --fix"
