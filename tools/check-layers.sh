#!/usr/bin/env bash
# Checks that the floors of nclink read one way: every #include of every file
# under src/ and include/nclink/ against the table in src/layers.txt. A module
# may include itself and the modules its line names; a public header counts
# as part of the module that owns it. Exit 0 when clean, 1 with one line per
# upward (or unknown) include otherwise. The `library` lines of the table put
# each module in one library; a module may include modules of its own
# library or of one listed before it (the terminal library holds no plant
# code).
#   tools/check-layers.sh [ROOT]     (ROOT: a source tree, default: this one)
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
table="$root/src/layers.txt"
[[ -f $table ]] || { echo "check-layers: no $table" >&2; exit 2; }

declare -A allowed owner library rank
libraries=0
while IFS= read -r line; do
  line=${line%%#*}
  [[ -z ${line// } ]] && continue
  if [[ $line =~ ^library[[:space:]]+([a-z_]+):(.*)$ ]]; then
    rank[${BASH_REMATCH[1]}]=$libraries
    libraries=$((libraries + 1))
    for m in ${BASH_REMATCH[2]}; do library[$m]=${BASH_REMATCH[1]}; done
  elif [[ $line =~ ^public[[:space:]]+([a-z_]+):(.*)$ ]]; then
    for h in ${BASH_REMATCH[2]}; do owner[$h]=${BASH_REMATCH[1]}; done
  elif [[ $line =~ ^([a-z_]+):(.*)$ ]]; then
    allowed[${BASH_REMATCH[1]}]=" ${BASH_REMATCH[1]} ${BASH_REMATCH[2]} "
  fi
done <"$table"

bad=0
complain() { echo "$1"; bad=1; }

# The table itself: a module's line names no module of a library after its own.
for m in "${!allowed[@]}"; do
  for d in ${allowed[$m]}; do
    [[ -n ${library[$m]:-} && -n ${library[$d]:-} ]] || continue
    ((${rank[${library[$d]}]} <= ${rank[${library[$m]}]})) ||
      complain "src/layers.txt: $m (${library[$m]} library) names $d of the ${library[$d]} library"
  done
done
for m in "${!library[@]}"; do
  [[ -n ${allowed[$m]:-} ]] || complain "src/layers.txt: library line names $m, which has no module line"
done

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
      { complain "$rel:$n: ${module#public:} includes $target of $dep, which src/layers.txt does not put below it"; continue; }
    local from=${library[${module#public:}]:-} to=${library[$dep]:-}
    [[ -n $from && -n $to ]] || continue   # reported below: a module without a library
    ((${rank[$to]} <= ${rank[$from]})) ||
      complain "$rel:$n: ${module#public:} ($from library) includes $target of $dep ($to library): the $from library may not use the $to library"
  done <"$file"
}

for dir in "$root"/src/*/; do
  module=$(basename "$dir")
  [[ -n ${allowed[$module]:-} ]] || { complain "src/$module/ is not a module of src/layers.txt"; continue; }
  [[ -n ${library[$module]:-} ]] || complain "src/$module/ is in no library line of src/layers.txt"
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
