#!/usr/bin/env bash
# How close the hierarchy's completions stay to the capture's relief, by
# levels and seed: paper 000's bark (W 3, R 4, spacing 0.0333), the
# 2000-vertex cylinder-bands (defaults) and paper 001's cylinder (420
# vertices, W 2, R 4, spacing 0.128), each completed with the exhaustive
# search for M in LEVELS and seeds 1..SEEDS, then `relief eval --truth`:
# MSI difference (mean |height| of the completed part against the
# captured part's, issue 7's bound 5 %), the displacement histogram's
# distance, the seam ratio, and the pattern lean and orientation distances
# (lower is closer). Prints every run and, per case and M, the median and
# range of the MSI difference. Quality only: bench/run.sh hierarchy times.
#   bench/hierarchy_quality.sh [CASE ...]   (bark, bands, p001; default all)
# Environment: OUT (default bench-out/hierarchy_quality), BUILD (default
# build), SEEDS (default 3), LEVELS (default "2 3 4 5" for the bark; the
# bands take 3, paper 001's cylinder 2, as bench/run.sh does).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench-out/hierarchy_quality}
BUILD=${BUILD:-build}
SEEDS=${SEEDS:-3}
LEVELS=${LEVELS:-2 3 4 5}
cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief >/dev/null
relief=$BUILD/relief
mkdir -p "$OUT"
# name, synth arguments, complete arguments, levels
cases=(
  "bark|cylinder-bark --colour --vertices 7150|--spacing 0.0333 --window 3 --rotations 4|$LEVELS"
  "bands|cylinder-bands --vertices 2000||3"
  "p001|cylinder-bands --vertices 420|--spacing 0.128 --window 2 --rotations 4|2"
)
want=("$@")
csv=$OUT/hierarchy_quality.csv
echo "case,levels,seed,msi_diff_percent,hist_distance,seam_ratio,lean_distance,orientation_distance" >"$csv"
for c in "${cases[@]}"; do
  IFS='|' read -r name synth args levels <<<"$c"
  if [[ ${#want[@]} -gt 0 && ! " ${want[*]} " =~ " $name " ]]; then continue; fi
  # shellcheck disable=SC2086
  "$relief" synth $synth -o "$OUT/${name}.ply" --truth "$OUT/${name}_truth.ply" >/dev/null 2>&1
  for m in $levels; do
    for ((seed = 1; seed <= SEEDS; ++seed)); do
      out=$OUT/${name}_M${m}_s${seed}.ply
      # shellcheck disable=SC2086
      "$relief" complete "$OUT/${name}.ply" -o "$out" --seed "$seed" --levels "$m" \
        --search exhaustive $args 2>/dev/null
      "$relief" eval "$out" --truth "$OUT/${name}_truth.ply" 2>&1 | awk -v c="$name" -v m="$m" -v s="$seed" '
        /^msi_diff_percent/ {msi = $2} /^hist_distance_displacement/ {h = $2}
        /seam_ratio/ {seam = $NF} /^pattern_lean_distance/ {l = $2}
        /^pattern_orientation_distance/ {o = $2}
        END {printf "%s,%s,%s,%s,%s,%s,%s,%s\n", c, m, s, msi, h, seam, l, o}' | tee -a "$csv"
    done
  done
done
echo "case, M: MSI difference median (min..max) over $SEEDS seeds"
sort -t, -k1,1 -k2,2n -k4,4g <(tail -n +2 "$csv") | awk -F, '
  function flush() { if (n) printf "%-6s M %s: %.2f %% (%.2f..%.2f)\n", k1, k2, v[int((n + 1) / 2)], v[1], v[n] }
  {key = $1 "," $2; if (key != last) { flush(); n = 0; last = key; k1 = $1; k2 = $2 } v[++n] = $4}
  END { flush() }'
