#!/usr/bin/env bash
# Redraw README's pictures of relief complete-points (bench/figures/points_*.png)
# from the cuts and results bench/points.sh leaves in its OUT folder:
# - points_bunny.png: a 2.6 cm crop about the bunny's 1.5 cm cut, seen along
#   its normal, shaded grey: the capture, --smooth-only,
#   --no-detail-histogram, the default, the scan (meshes: --mesh);
# - points_frag115.png, points_milk.png: the capture, --smooth-only and the
#   default in the scans' own colours.
#   usage: bench/points_pictures.sh [POINTS_OUT] [BUILD_DIR]
#          (defaults bench-out/points, build; run bench/points.sh first)
set -euo pipefail
cd "$(dirname "$0")/.."
in=${1:-bench-out/points}
relief=${2:-build}/relief
out=bench/figures
for f in bunny_capture bunny_whole frag115_capture milk_capture; do
  [[ -f $in/$f.ply ]] || { echo "points_pictures: $in/$f.ply missing: run bench/points.sh" >&2; exit 1; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
row() { /usr/bin/python3 bench/png_row.py "$@"; }

# The bunny: the cut's centre (points.py snaps it to the nearest vertex) and
# the mean normal about it.
centre=-0.02743300050497055,0.08082800358533859,0.04845000058412552
view=-171,60
"$relief" complete-points "$in/bunny_capture.ply" -o "$tmp/s.ply" --mesh "$tmp/s_mesh.ply" --smooth-only --quiet
"$relief" complete-points "$in/bunny_capture.ply" -o "$tmp/n.ply" --mesh "$tmp/n_mesh.ply" --no-detail-histogram --quiet
"$relief" complete-points "$in/bunny_capture.ply" -o "$tmp/d.ply" --mesh "$tmp/d_mesh.ply" --quiet
panels=()
for m in "$in/bunny_capture.ply" "$tmp/s_mesh.ply" "$tmp/n_mesh.ply" "$tmp/d_mesh.ply" "$in/bunny_whole.ply"; do
  b=$tmp/crop_${#panels[@]}
  "$relief" cut "$m" -o "$b.ply" --crop --ball "$centre,0.026" 2>/dev/null
  "$relief" render "$b.ply" -o "$b.png" --view "$view" --size 400x400 --colour-by none 2>/dev/null
  panels+=("$b.png")
done
row "$out/points_bunny.png" "${panels[@]}"

for c in "frag115 -170.4,-43.6" "milk -82.8,49.6"; do
  set -- $c
  panels=()
  for v in capture smooth-only relief; do
    "$relief" render "$in/${1}_$v.ply" -o "$tmp/${1}_$v.png" --size 400x300 --view "$2" 2>/dev/null
    panels+=("$tmp/${1}_$v.png")
  done
  row "$out/points_$1.png" "${panels[@]}"
done
echo "points_pictures: $out/points_bunny.png, points_frag115.png, points_milk.png"
