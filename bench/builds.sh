#!/usr/bin/env bash
# Two builds of `relief complete` side by side: the same completions run by
# OLD and NEW in turn (OLD, NEW, OLD, NEW, ...), REPS times each (default
# 3), on real captures cut where their truth is known (the ggg statue's
# knee, the fluted pot's wall) and on the demo's bark (defaults, two
# levels, and a low e that rejects and raises it). Prints a Markdown table:
# the growth's seconds (the report's) and the wall's, each min-max and
# median, the median ratio OLD / NEW, and whether the two builds wrote the
# same bytes (every repetition compared). For a change that claims to
# speed the growth up and leave its output alone.
#   bench/builds.sh OLD/relief NEW/relief [DATA_DIR]   (REPS, CASES=1,3,...)
set -euo pipefail
old=${1:?usage: bench/builds.sh OLD/relief NEW/relief [DATA_DIR]}
new=${2:?usage: bench/builds.sh OLD/relief NEW/relief [DATA_DIR]}
data=${3:-$(cd "$(dirname "$0")/.." && pwd)/../shared/data}/real/ggg_sfm
REPS=${REPS:-3}
CASES=${CASES:-1,2,3,4,5}
for b in "$old" "$new"; do [[ -x $b ]] || { echo "builds.sh: $b: not an executable" >&2; exit 1; }; done
[[ -f $data/Angel.ply ]] || { echo "builds.sh: $data: no ggg_sfm captures" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$new" cut "$data/Angel.ply" --ball 13.11,-64.51,16.35,15 -o "$tmp/angel.ply" 2>/dev/null
"$new" cut "$data/plasticVase.ply" --ball 177.05,-4.25,274.94,30 -o "$tmp/pot.ply" 2>/dev/null
"$new" synth cylinder-bark --seed 1 -o "$tmp/bark.ply" 2>/dev/null
# number|name|input|options
cases=("1|statue, knee cut (smooth base, coherent)|angel.ply|"
       "2|fluted pot, wall cut (smooth base, coherent)|pot.ply|"
       "3|the demo's bark (exhaustive search)|bark.ply|"
       "4|the bark, --levels 2|bark.ply|--levels 2"
       "5|the bark, --error 0.03 (rejections, raises)|bark.ply|--error 0.03")
rows=$tmp/rows.txt
for c in "${cases[@]}"; do
  IFS='|' read -r num name input opts <<<"$c"
  [[ ,$CASES, == *,$num,* ]] || continue
  same=same
  for rep in $(seq 1 "$REPS"); do
    for which in old new; do
      bin=$old; [[ $which == new ]] && bin=$new
      t0=$(date +%s.%N)
      # shellcheck disable=SC2086
      "$bin" complete "$tmp/$input" -o "$tmp/$which.ply" --report "$tmp/$which.json" --quiet $opts
      t1=$(date +%s.%N)
      g=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["growth"]["seconds"])' "$tmp/$which.json")
      echo "$num|$name|$which|$g|$(echo "$t1 - $t0" | bc)" >> "$rows"
    done
    cmp -s "$tmp/old.ply" "$tmp/new.ply" || same=DIFFERENT
  done
  echo "$num|$name|bytes|$same|" >> "$rows"
done

python3 - "$rows" "$REPS" <<'PY'
import statistics as st, sys
rows = [l.rstrip("\n").split("|") for l in open(sys.argv[1])]
print("| case | growth, old | growth, new | old / new | wall, old | wall, new | old / new | bytes |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
def cell(v): return "%.2f-%.2f s (%.2f)" % (min(v), max(v), st.median(v))
for num in dict.fromkeys(r[0] for r in rows):
    rs = [r for r in rows if r[0] == num]
    get = lambda which, i: [float(r[i]) for r in rs if r[2] == which]
    go, gn, wo, wn = get("old", 3), get("new", 3), get("old", 4), get("new", 4)
    same = [r[3] for r in rs if r[2] == "bytes"][0]
    print("| %s | %s | %s | **%.2f** | %s | %s | %.2f | %s |" % (
        rs[0][1], cell(go), cell(gn), st.median(go) / st.median(gn), cell(wo), cell(wn),
        st.median(wo) / st.median(wn), same))
print("\n(medians of %s runs each, the builds alternating)" % sys.argv[2])
PY
