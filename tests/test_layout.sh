#!/usr/bin/env bash
# The layering of host/ (docs/design.md, Layout): each folder includes only itself,
# the public header (relief/), the shared math header (kernels/) where the
# table allows it, and the folders listed for it; lower folders never include
# higher ones. Also: every include names its folder, no source file sits
# directly in host/, no include climbs out with "../", and numbers are read
# only through base/numtext.h (the C locale whatever the caller's).
#   tests/test_layout.sh [SOURCE_DIR]
set -euo pipefail
src=${1:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$src/host"

# folder: what it may include besides itself and relief/
declare -A allowed=(
  [base]=""
  [device]="base"
  [mesh]="base"
  [smooth]="base mesh kernels"
  [match]="base mesh smooth device kernels"
  [grow]="base mesh smooth match kernels"
  [report]="base mesh smooth match grow"
  [synth]="base mesh"
  [image]="base report match device kernels"
  [depth]="base mesh smooth report match image kernels"
  [points]="base mesh smooth match device depth kernels"
  [complete]="base mesh smooth match grow report points"
  [occlude]="base mesh smooth report image depth"
  [cli]="base mesh smooth match grow report synth image depth points complete occlude"
)

fail=0
complain() { echo "layout: $*" >&2; fail=1; }

for f in *; do
  [[ -f $f ]] && complain "host/$f: a file directly in host/; it belongs in one of its folders"
done
for dir in */; do
  dir=${dir%/}
  [[ -v allowed[$dir] ]] || { complain "host/$dir/: a folder the layering table does not know; add it to tests/test_layout.sh and docs/design.md's Layout"; continue; }
  ok=" $dir relief ${allowed[$dir]} "
  while IFS=: read -r file line text; do
    name=${text#*\"}; name=${name%%\"*}
    case $name in
      ../*|*/../*) complain "host/$file:$line: \"$name\" climbs out of its folder"; continue ;;
      */*) ;;
      *) complain "host/$file:$line: \"$name\" does not name its folder (\"FOLDER/$name\")"; continue ;;
    esac
    top=${name%%/*}
    [[ $ok == *" $top "* ]] ||
      complain "host/$file:$line: $dir/ may not include $name (allowed: ${allowed[$dir]:-none})"
  done < <(grep -Hn '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$dir"/* || true)
done
# strtod and the scanf family follow the caller's LC_NUMERIC ("0.5" stops at
# the '.' under a comma-decimal locale): host/ reads numbers with
# relief_strtod (base/numtext.h, issue 60). Integers (strtol) are the same
# in every locale.
while IFS= read -r hit; do
  complain "host/$hit: reads a number in the caller's locale; use relief_strtod (base/numtext.h)"
done < <(grep -rnE '\b(strto(d|f|ld)|atof|v?f?scanf|v?sscanf)[[:space:]]*\(' \
           --include='*.c' --include='*.cpp' --include='*.h' . | grep -v '^\./base/numtext\.' |
         sed 's|^\./||' || true)
if [[ $fail -ne 0 ]]; then
  echo "layout: FAILED" >&2
  exit 1
fi
echo "layout: host/ keeps its layering ($(ls -d */ | wc -l) folders, $(ls */* | wc -l) files)"
