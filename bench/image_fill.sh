#!/usr/bin/env bash
# relief image-fill against its own references (scalar, OpenCL, --exhaustive)
# and against OpenCV's inpainting (Telea, Navier-Stokes), on the images of
# ../shared/data/images with holes cut where the truth is known
# (bench/image_fill.py says what is measured); then the scorers side by
# side in one process (bench_image_fill: scalar, OpenCL reading every score
# back, OpenCL selecting on the device), on those images with a 64 x 64
# hole and on a paper-sized atlas (coffee.png tiled to 8192 x 1024, eight
# holes). OpenCV is a peer to compare with, never linked: python3-opencv is
# installed here (as root) if missing.
#   bench/image_fill.sh [--repeat N] [--no-exhaustive]
# Environment: OUT (default bench-out/image_fill), BUILD (default build),
# PYTHON (default /usr/bin/python3).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench-out/image_fill}
BUILD=${BUILD:-build}
./setup.sh deps
. bench/peers.sh # PY, python3-opencv
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELIEF_BUILD_BENCH=ON >/dev/null
cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief bench_image_fill >/dev/null
mkdir -p "$OUT"
"$PY" bench/image_fill.py "$BUILD/relief" ../shared/data/images "$OUT" "$@"
echo "bench: $OUT/image_fill.csv"
"$PY" - "$OUT" <<'PY'
import sys, cv2, numpy as np
out = sys.argv[1]
atlas = np.tile(cv2.imread("../shared/data/images/coffee.png"), (3, 14, 1))[:1024, :8192]
cv2.imwrite(out + "/atlas.png", atlas)
m = np.zeros(atlas.shape[:2], np.uint8)
for i in range(8):
    cv2.rectangle(m, (500 + i * 1000, 300), (560 + i * 1000 + 20 * i, 420), 255, -1)
cv2.imwrite(out + "/atlas_mask.png", m)
PY
"$BUILD/bench/bench_image_fill" ../shared/data/images --repeat 5 --csv "$OUT/scorers.csv" \
  --atlas "$OUT/atlas.png" --atlas-mask "$OUT/atlas_mask.png"
echo "bench: $OUT/scorers.csv"
