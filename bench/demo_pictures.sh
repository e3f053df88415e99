#!/usr/bin/env bash
# Regenerate README's pictures of the demo (bench/figures/demo_*.png): the
# capture's front, the truth's back, and the completed back with the defaults
# and with --coherence 2; and of --fill (bench/figures/fill_*.png): a hole in
# a patch of Max Planck's crown (../shared/data/real) completed alone, and
# the whole sphere --fill whole would complete.
#   usage: bench/demo_pictures.sh [BUILD_DIR]   (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
relief=${1:-build}/relief
out=bench/figures
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$relief" synth cylinder-bark --colour --seed 1 -o "$tmp/capture.ply" --truth "$tmp/truth.ply"
"$relief" complete "$tmp/capture.ply" -o "$tmp/back.ply" --quiet
"$relief" complete "$tmp/capture.ply" -o "$tmp/back2.ply" --quiet --coherence 2
view() { "$relief" render "$1" -o "$out/$2" --view "$3" --size 320x300; }
view "$tmp/capture.ply" demo_captured.png 0,10
view "$tmp/truth.ply" demo_truth_back.png 180,10
view "$tmp/back.ply" demo_back.png 180,10
view "$tmp/back2.ply" demo_back_coherence2.png 180,10
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
