#!/usr/bin/env bash
# relief complete-points (paper 002) on holes cut from the real scans and
# point sets of ../shared/data, beside the smooth RBF fill alone and Open3D's
# Poisson reconstruction (bench/points.py says what is measured). Open3D is
# a peer to compare with, never linked: python3-open3d is installed here
# (as root) if missing.
#   bench/points.sh [--repeat N] [--no-open3d] [--no-scale]
# Environment: OUT (default bench-out/points), BUILD (default build),
# PYTHON (default /usr/bin/python3).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench-out/points}
BUILD=${BUILD:-build}
./setup.sh deps
PEER_MODULE=open3d PEER_PACKAGE=python3-open3d . bench/peers.sh # PY, python3-open3d
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELIEF_BUILD_BENCH=ON >/dev/null
cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief points_bench_tool >/dev/null
mkdir -p "$OUT"
"$PY" bench/points.py "$BUILD/relief" "$BUILD/bench/points_bench_tool" ../shared/data "$OUT" "$@"
echo "bench: $OUT/points.csv"
