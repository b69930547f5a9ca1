#!/usr/bin/env bash
# Extracts every fenced block whose info string is `cpp` or `c` from the
# Markdown files given and compiles each as its own translation unit:
#   c++ -std=c++17 -Wall -Wextra -Werror -fsyntax-only -include prelude.hpp
#   cc  -std=c11   -Wall -Wextra -Werror -fsyntax-only -include prelude.h
# A block opened with ```cpp ignore (or ```c ignore) is skipped and counted.
# Fails naming file and line of every block that does not compile.
#   check_doc_blocks.sh CXX CC INCLUDE_DIR PRELUDE_DIR WORK_DIR FILE.md...
set -u
cxx=$1 cc=$2 include=$3 prelude=$4 work=$5
shift 5
rm -rf "$work" && mkdir -p "$work"
compiled=0 skipped=0 failed=0
for doc in "$@"; do
    name=$(basename "$doc" .md)
    # One file per block: NAME-INDEX-LINE.LANG (LANG cpp, c or ignore).
    awk -v dir="$work" -v name="$name" -v doc="$doc" '
        !inblock && /^```(cpp|c)( +ignore)?[ \t]*$/ {
            inblock = 1; index_ += 1
            lang = ($0 ~ /^```cpp/) ? "cpp" : "c"
            if ($0 ~ /ignore/) lang = "ignore"
            file = sprintf("%s/%s-%02d-%d.%s", dir, name, index_, NR, lang)
            printf("#line %d \"%s\"\n", NR + 1, doc) > file
            next
        }
        inblock && /^```/ { inblock = 0; close(file); next }
        inblock { print > file }
    ' "$doc"
done
for src in "$work"/*; do
    [ -e "$src" ] || continue
    case "$src" in
        *.ignore) skipped=$((skipped + 1)); continue ;;
        *.cpp) cmd=("$cxx" -std=c++17 -Wall -Wextra -Werror -fsyntax-only -include "$prelude/prelude.hpp" -I"$include" -I"$include/../drivers" "$src") ;;
        *.c) cmd=("$cc" -x c -std=c11 -Wall -Wextra -Werror -fsyntax-only -include "$prelude/prelude.h" -I"$include" -I"$include/../drivers" "$src") ;;
    esac
    compiled=$((compiled + 1))
    if ! out=$("${cmd[@]}" 2>&1); then
        failed=$((failed + 1))
        echo "FAILED: $(head -1 "$src" | sed 's/#line \([0-9]*\) "\(.*\)"/\2:\1/'): the block does not compile:"
        echo "$out"
    fi
done
echo "doc blocks: $compiled compiled, $failed failed, $skipped marked ignore"
[ "$compiled" -gt 0 ] && [ "$failed" -eq 0 ]
