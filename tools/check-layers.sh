#!/usr/bin/env bash
# Checks that the floors of nclink read one way: every #include of every file
# under src/ and include/nclink/ against the table in src/layers.txt. A module
# may include itself and the modules its line names; a public header counts
# as part of the module that owns it. Exit 0 when clean, 1 with one line per
# upward (or unknown) include otherwise.
#   tools/check-layers.sh [ROOT]     (ROOT: a source tree, default: this one)
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
table="$root/src/layers.txt"
[[ -f $table ]] || { echo "check-layers: no $table" >&2; exit 2; }

declare -A allowed owner
while IFS= read -r line; do
  line=${line%%#*}
  [[ -z ${line// } ]] && continue
  if [[ $line =~ ^public[[:space:]]+([a-z_]+):(.*)$ ]]; then
    for h in ${BASH_REMATCH[2]}; do owner[$h]=${BASH_REMATCH[1]}; done
  elif [[ $line =~ ^([a-z_]+):(.*)$ ]]; then
    allowed[${BASH_REMATCH[1]}]=" ${BASH_REMATCH[1]} ${BASH_REMATCH[2]} "
  fi
done <"$table"

bad=0
complain() { echo "$1"; bad=1; }

# check FILE MODULE: every include of FILE must be visible from MODULE.
check() {
  local file=$1 module=$2 rel=${1#"$root"/} n=0 line target dep
  while IFS= read -r line; do
    n=$((n + 1))
    [[ $line =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*([\"\<])([^\"\>]+)[\"\>] ]] || continue
    target=${BASH_REMATCH[2]}
    if [[ $target == nclink/* ]]; then
      dep=${owner[${target#nclink/}]:-}
      [[ -n $dep ]] || { complain "$rel:$n: <$target> is not in the public-header table of src/layers.txt"; continue; }
    elif [[ ${BASH_REMATCH[1]} == '"' && $target == */* ]]; then
      dep=${target%%/*}
      [[ -d $root/src/$dep ]] || continue   # not a module path (e.g. a relative include)
      [[ $module == public:* ]] && { complain "$rel:$n: a public header includes the private \"$target\""; continue; }
    else
      continue
    fi
    [[ ${allowed[${module#public:}]} == *" $dep "* ]] ||
      complain "$rel:$n: ${module#public:} includes $target of $dep, which src/layers.txt does not put below it"
  done <"$file"
}

for dir in "$root"/src/*/; do
  module=$(basename "$dir")
  [[ -n ${allowed[$module]:-} ]] || { complain "src/$module/ is not a module of src/layers.txt"; continue; }
  while IFS= read -r -d '' f; do check "$f" "$module"; done < <(find "$dir" -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -print0)
done
while IFS= read -r -d '' f; do
  h=${f#"$root"/include/nclink/}
  m=${owner[$h]:-}
  [[ -n $m ]] || { complain "include/nclink/$h has no owning module in src/layers.txt"; continue; }
  check "$f" "public:$m"
done < <(find "$root/include/nclink" -type f \( -name '*.hpp' -o -name '*.h' \) -print0)

if ((bad)); then
  echo "check-layers: upward or unknown includes found (see src/layers.txt and docs/architecture.md)" >&2
  exit 1
fi
echo "check-layers: every include of src/ and include/nclink/ goes down or sideways"
