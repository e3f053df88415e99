#!/usr/bin/env bash
# The README's pictures of issue 43 (occluders from depth, paper 004 ch. 2):
# office1.pcd (a Kinect frame) and the synthetic RGB-D frame of
# tests/api/test_api_occluders.c, each as its colour, the mask found by
# `relief occluders` (occluders tinted red) and the colour and depth after
# `relief remove-occluders` (defaults), the depths as grey (near bright,
# missing black, one scale per frame).
#   bench/occluders_pictures.sh [BUILD_DIR] [DATA_DIR]   (writes bench/figures/occluders_*.png)
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build}
data=${2:-$src/../shared/data}/depth
out=$src/bench/figures
py=$src/.venv/bin/python
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/tests/test_api_occluders" --write "$tmp"
for name in office1 synthetic; do
  in=$data/office1.pcd
  [[ $name == synthetic ]] && in=$tmp/scene.pcd
  "$build/bench/depth_bench_tool" rgb "$in" "$tmp/${name}_colour.png"
  /usr/bin/time -f "$name occluders: %e s" "$build/relief" occluders "$in" -o "$tmp/${name}_mask.png" \
    --overlay "$tmp/${name}_overlay.png" --report "$tmp/${name}_occluders.json"
  /usr/bin/time -f "$name remove-occluders: %e s" "$build/relief" remove-occluders "$in" \
    -o "$tmp/${name}_out.pcd" --colour-out "$tmp/${name}_after.png" --quiet
  "$build/bench/depth_bench_tool" pfm "$in" "$tmp/${name}_before.pfm"
  "$build/bench/depth_bench_tool" pfm "$tmp/${name}_out.pcd" "$tmp/${name}_after.pfm"
  "$py" - "$tmp/${name}_before.pfm" "$tmp/${name}_after.pfm" \
    "$tmp/${name}_zbefore.png" "$tmp/${name}_zafter.png" <<'PY'
import sys
import numpy as np
import relief
a, b = relief.read_depth(sys.argv[1]), relief.read_depth(sys.argv[2])
lo, hi = np.percentile(a[np.isfinite(a)], [1, 99])
for d, path in ((a, sys.argv[3]), (b, sys.argv[4])):
    v = np.clip((hi - d) / (hi - lo), 0, 1) * 215 + 40
    v = np.where(np.isfinite(d), v, 0).astype(np.uint8)
    relief.write_image(path, np.repeat(v[:, :, None], 3, axis=2))
PY
  "$py" "$src/bench/png_row.py" "$out/occluders_${name}_colour.png" \
    "$tmp/${name}_colour.png" "$tmp/${name}_overlay.png" "$tmp/${name}_after.png"
  "$py" "$src/bench/png_row.py" "$out/occluders_${name}_depth.png" \
    "$tmp/${name}_zbefore.png" "$tmp/${name}_zafter.png"
done
echo "occluders_pictures: bench/figures/occluders_{office1,synthetic}_{colour,depth}.png"
