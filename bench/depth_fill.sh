#!/usr/bin/env bash
# relief depth-fill's three variants on both scorers against OpenCV's
# inpainting (Telea, Navier-Stokes), on holes cut from the real frames of
# ../shared/data/depth where the truth is known (bench/depth_fill.py says
# what is measured). OpenCV is a peer to compare with, never linked:
# python3-opencv is installed here (as root) if missing.
#   bench/depth_fill.sh [--repeat N]
# Environment: OUT (default bench-out/depth_fill), BUILD (default build),
# PYTHON (default /usr/bin/python3).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench-out/depth_fill}
BUILD=${BUILD:-build}
./setup.sh deps
. bench/peers.sh # PY, python3-opencv
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELIEF_BUILD_BENCH=ON >/dev/null
cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief depth_bench_tool >/dev/null
mkdir -p "$OUT"
"$PY" bench/depth_fill.py "$BUILD/relief" "$BUILD/bench/depth_bench_tool" ../shared/data/depth \
  "$OUT" "$@"
echo "bench: $OUT/depth_fill.csv"
