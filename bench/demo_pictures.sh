#!/usr/bin/env bash
# Regenerate README's pictures of the demo (bench/figures/demo_*.png): the
# capture's front, the truth's back, and the completed back with the defaults
# (demo_back_before.png, the defaults' back before the cylinder's lattice
# ran its rows along the axis, 884af49, is kept as it was drawn); and of --fill (bench/figures/fill_*.png): a hole in
# a patch of Max Planck's crown (../shared/data/real) completed alone, and
# the whole sphere --fill whole would complete; and of the searches
# (bench/figures/search_frag_*.png): a 16 cm disc cut from the depth-camera
# floor open3d_frag115 completed by the exhaustive search (about 3 minutes)
# and by the coherent one, heights off the fitted plane, beside the truth.
#   usage: bench/demo_pictures.sh [BUILD_DIR]   (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
relief=${1:-build}/relief
out=bench/figures
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$relief" synth cylinder-bark --colour --seed 1 -o "$tmp/capture.ply" --truth "$tmp/truth.ply"
"$relief" complete "$tmp/capture.ply" -o "$tmp/back.ply" --quiet
view() { "$relief" render "$1" -o "$out/$2" --view "$3" --size 320x300; }
view "$tmp/capture.ply" demo_captured.png 0,10
view "$tmp/truth.ply" demo_truth_back.png 180,10
view "$tmp/back.ply" demo_back.png 180,10
planck=../shared/data/real/max_planck/decimated-max.obj
if [[ -f $planck ]]; then
  "$relief" cut "$planck" --crop --ball 45.9,144.5,80,70 -o "$tmp/crown.ply"
  "$relief" cut "$tmp/crown.ply" --ball 26.8,144.5,100.2,22 -o "$tmp/crown_cap.ply"
  "$relief" complete "$tmp/crown_cap.ply" -o "$tmp/crown_done.ply" --quiet
  "$relief" smooth "$tmp/crown_cap.ply" -o "$tmp/crown_whole.ply" --fill whole --quiet
  "$relief" render "$tmp/crown_done.ply" -o "$out/fill_holes.png" --view 90,0 --size 320x300 --colour-by label
  "$relief" render "$tmp/crown_whole.ply" -o "$out/fill_whole.png" --view 60,20 --size 320x300 --colour-by label
else
  echo "demo_pictures: $planck not found; the --fill pictures are not redrawn" >&2
fi
frag=../shared/data/real/open3d_frag115/frag_115.ply
if [[ -f $frag ]]; then
  disc=1.65835,1.88511,1.06949
  "$relief" cut "$frag" --ball $disc,0.08 -o "$tmp/frag_cap.ply" --truth "$tmp/frag_truth.ply"
  "$relief" cut "$tmp/frag_truth.ply" --crop --ball $disc,0.16 -o "$tmp/frag_truth_c.ply"
  "$relief" render "$tmp/frag_truth_c.ply" -o "$out/search_frag_truth.png" --size 320x300 --colour-by displacement
  for search in exhaustive coherent; do
    "$relief" complete "$tmp/frag_cap.ply" -o "$tmp/frag_$search.ply" --oversample 0 --spacing 0.005 \
      --frames primitive --rotations 1 --search $search --quiet
    "$relief" cut "$tmp/frag_$search.ply" --crop --ball $disc,0.16 -o "$tmp/frag_${search}_c.ply"
    "$relief" render "$tmp/frag_${search}_c.ply" -o "$out/search_frag_$search.png" --size 320x300 \
      --colour-by displacement
  done
else
  echo "demo_pictures: $frag not found; the search pictures are not redrawn" >&2
fi
