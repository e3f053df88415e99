#!/usr/bin/env bash
# relief image-fill (its default method and --method jain; the one method of
# a binary without --method) against the peers a user would pick instead:
# OpenCV's Telea, Navier-Stokes, FSR (xphoto, fast; best with --fsr-best)
# and shift-map, PatchMatch (pypatchmatch) and GIMP Resynthesizer's engine
# with Heal selection's settings (PyPI resynthesizer), on the images of
# ../shared/data/images with holes cut where the truth is known: a disc,
# two rectangles of 12 % of the area, 5-pixel scratches (lines, a curve).
# bench/image_fill.py says what is measured. The peers are pip packages in
# the bench's own venv (bench/.venv-image, git-ignored), run from Python,
# never linked. Writes OUT/image_fill.csv and OUT/image_fill.md (medians
# per hole class and method); --figures DIR, a picture strip per hole.
# --scorers: then also the scorers side by side in one process
# (bench_image_fill: scalar, OpenCL reading every score back, OpenCL
# selecting on the device), on those images with a 64 x 64 hole and on a
# paper-sized atlas (coffee.png tiled to 8192 x 1024, eight holes).
#   bench/image_fill.sh [--repeat N] [--only IMAGE,...] [--figures DIR]
#                       [--fsr-best] [--seed N] [--scorers]
# Environment: RELIEF (default BUILD/relief, built incrementally when not
# given), BUILD (default build), OUT (default bench/out/image_fill), DATA
# (default ../shared/data), VENV (default bench/.venv-image), PYTHON (the
# venv's maker, default python3). Without --fsr-best about 5 minutes on 2
# cores; --fsr-best adds about 10.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench/out/image_fill}
BUILD=${BUILD:-build}
DATA=${DATA:-../shared/data}
VENV=${VENV:-bench/.venv-image}
scorers=0
args=()
for a in "$@"; do
  if [[ $a == --scorers ]]; then scorers=1; else args+=("$a"); fi
done
if [[ -z ${RELIEF:-} ]]; then
  RELIEF=$BUILD/relief
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief >/dev/null
fi
[[ -x $RELIEF ]] || { echo "bench: no relief at $RELIEF" >&2; exit 1; }
PEERS="numpy opencv-contrib-python-headless scikit-image pypatchmatch resynthesizer"
if ! "$VENV/bin/python" -c "import numpy, cv2, cv2.xphoto, skimage, patchmatch, resynthesizer" 2>/dev/null; then
  echo "bench: installing the peers into $VENV ($PEERS)"
  "${PYTHON:-python3}" -m venv "$VENV"
  "$VENV/bin/pip" install -q --upgrade pip >/dev/null
  # shellcheck disable=SC2086
  "$VENV/bin/pip" install -q $PEERS
fi
"$VENV/bin/python" -c "from importlib.metadata import version as v
print('bench: peers: ' + ', '.join('%s %s' % (p, v(p)) for p in ('opencv-contrib-python-headless', 'pypatchmatch', 'resynthesizer', 'scikit-image')))"
mkdir -p "$OUT"
"$VENV/bin/python" bench/image_fill.py "$RELIEF" "$DATA/images" "$OUT" "${args[@]}"
echo "bench: $OUT/image_fill.csv, $OUT/image_fill.md"
[[ $scorers -eq 1 ]] || exit 0
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELIEF_BUILD_BENCH=ON >/dev/null
cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target bench_image_fill >/dev/null
"$VENV/bin/python" - "$OUT" "$DATA/images" <<'PY'
import sys, cv2, numpy as np
out, images = sys.argv[1], sys.argv[2]
atlas = np.tile(cv2.imread(images + "/coffee.png"), (3, 14, 1))[:1024, :8192]
cv2.imwrite(out + "/atlas.png", atlas)
m = np.zeros(atlas.shape[:2], np.uint8)
for i in range(8):
    cv2.rectangle(m, (500 + i * 1000, 300), (560 + i * 1000 + 20 * i, 420), 255, -1)
cv2.imwrite(out + "/atlas_mask.png", m)
PY
"$BUILD/bench/bench_image_fill" "$DATA/images" --repeat 5 --csv "$OUT/scorers.csv" \
  --atlas "$OUT/atlas.png" --atlas-mask "$OUT/atlas_mask.png"
echo "bench: $OUT/scorers.csv"
