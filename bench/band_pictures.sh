#!/usr/bin/env bash
# The README's pictures of a capture that goes all round its cylinder
# (issue 40): a band of synth cylinder-bands with a cut in its wall and a
# notch in its top edge, completed by `relief complete` with default options
# (its hole only: the band has no hidden side) and with --fill whole (the
# notch and the cylinder's rest too, as before), new vertices orange; and
# the notch selected with a hole mask (its rim is part of the border: filled
# in part, seen from the notch's side).
#   bench/band_pictures.sh [BUILD_DIR]     (writes bench/figures/band_*.png)
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
relief=${1:-$src/build}/relief
out=$src/bench/figures
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$relief" synth cylinder-bands -o "$tmp/cb.ply" --truth "$tmp/cbt.ply" --vertices 6000 2>/dev/null
"$relief" cut "$tmp/cbt.ply" --ball 1,0,2,0.35 -o "$tmp/cbn.ply" 2>/dev/null
"$relief" cut "$tmp/cbn.ply" --ball -1,0,1,0.3 -o "$tmp/band.ply" 2>/dev/null
"$relief" complete "$tmp/band.ply" -o "$tmp/auto.ply" --quiet
"$relief" complete "$tmp/band.ply" -o "$tmp/whole.ply" --fill whole --quiet
view=180,25 # the cut in front, the notch at the back
"$relief" render "$tmp/band.ply" -o "$out/band_cut.png" --view $view --size 300x300 >/dev/null 2>&1
"$relief" render "$tmp/auto.ply" -o "$out/band_auto.png" --colour-by label --view $view --size 300x300 >/dev/null 2>&1
"$relief" render "$tmp/whole.ply" -o "$out/band_whole.png" --colour-by label --view $view --size 300x300 >/dev/null 2>&1
# The notch alone, by a hole mask at it, seen from its side.
"$relief" complete "$tmp/band.ply" -o "$tmp/notch.ply" --hole-mask ball:1,0,2,0.45 --quiet
"$relief" render "$tmp/band.ply" -o "$out/band_notch_cut.png" --view 0,20 --size 300x300 >/dev/null 2>&1
"$relief" render "$tmp/notch.ply" -o "$out/band_notch.png" --colour-by label --view 0,20 --size 300x300 >/dev/null 2>&1
echo "pictures in $out/band_*.png"
