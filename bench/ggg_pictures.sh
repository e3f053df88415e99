#!/usr/bin/env bash
# The README's pictures of issue 40 (real captures as they come): a hole cut
# in each ggg_sfm photogrammetry capture (a vase's wall, the fluted pot's,
# the statue's knee), completed by `relief complete`, `relief
# complete-points` and `relief depth-fill` with default options: the repair
# on reading, the hole
# model (the cut filled; the vase's mouth and base, the statue's plinth left
# open), rendered with the new vertices orange.
#   bench/ggg_pictures.sh [BUILD_DIR] [DATA_DIR]     (writes bench/figures/ggg_*.png)
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
relief=${1:-$src/build}/relief
data=${2:-$src/../shared/data}/real/ggg_sfm
out=$src/bench/figures
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# name, file, the cut's ball, the view
cases=("vase blackVase 148.82,20.99,223.15,30 0,10"
       "pot plasticVase 177.05,-4.25,274.94,30 0,10"
       "angel Angel 13.11,-64.51,16.35,15 -90,10")
for c in "${cases[@]}"; do
  read -r name file ball view <<<"$c"
  "$relief" cut "$data/$file.ply" --ball "$ball" -o "$tmp/$name.ply" 2>/dev/null
  /usr/bin/time -f "$name complete: %e s" "$relief" complete "$tmp/$name.ply" -o "$tmp/${name}_c.ply" --quiet
  /usr/bin/time -f "$name complete-points: %e s" "$relief" complete-points "$tmp/$name.ply" \
    -o "$tmp/${name}_p.ply" --mesh "$tmp/${name}_pm.ply" --quiet
  /usr/bin/time -f "$name depth-fill: %e s" "$relief" depth-fill "$tmp/$name.ply" -o "$tmp/${name}_d.ply" --quiet
  "$relief" render "$tmp/${name}_d.ply" -o "$out/ggg_${name}_depth.png" --colour-by label \
    --view "$view" --size 360x360 >/dev/null 2>&1
  "$relief" render "$tmp/$name.ply" -o "$out/ggg_${name}_cut.png" --view "$view" --size 360x360 >/dev/null 2>&1
  "$relief" render "$tmp/${name}_c.ply" -o "$out/ggg_${name}_complete.png" --colour-by label \
    --view "$view" --size 360x360 >/dev/null 2>&1
  "$relief" render "$tmp/${name}_pm.ply" -o "$out/ggg_${name}_points.png" --colour-by label \
    --view "$view" --size 360x360 >/dev/null 2>&1
done
echo "pictures in $out/ggg_*.png"
