#!/usr/bin/env bash
# relief depth-fill at depth steps (issue 63) on the shared real frames'
# own holes: the five registered living-room frames, NYU's basement, SUN's
# corridor (../shared/data/rgbd) and office1.pcd (../shared/data/depth).
# Each frame is filled by relief with --edges layers (the default; with its
# colour), --edges across (paper 003) and OpenCV's Telea (a peer, never
# linked). bench/depth_edges.py measures the share of the filled pixels in
# gaps across steps over 0.3 m that lie within 0.1 m of an end (the
# issue's measure, its 2-D reading and its interior part); seconds are
# medians of --repeat N. --figures DIR writes, per frame, the depth before
# and after each fill and a view from above of the points (grey captured,
# red filled). The peer is a pip package in bench/.venv-image (git-ignored).
#   bench/depth_edges.sh [--repeat N] [--only FRAME,...] [--figures DIR]
# Environment: RELIEF (default BUILD/relief), BUILD (default build), OUT
# (default bench/out/depth_edges), DATA (default ../shared/data), VENV
# (default bench/.venv-image), PYTHON (the venv's maker, default python3).
# About 2 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench/out/depth_edges}
BUILD=${BUILD:-build}
DATA=${DATA:-../shared/data}
VENV=${VENV:-bench/.venv-image}
if [[ -z ${RELIEF:-} ]]; then
  RELIEF=$BUILD/relief
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELIEF_BUILD_BENCH=ON >/dev/null
  cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief depth_bench_tool >/dev/null
fi
[[ -x $RELIEF ]] || { echo "bench: no relief at $RELIEF" >&2; exit 1; }
if ! "$VENV/bin/python" -c "import numpy, cv2" 2>/dev/null; then
  echo "bench: installing numpy and opencv-contrib-python-headless into $VENV"
  "${PYTHON:-python3}" -m venv "$VENV"
  "$VENV/bin/pip" install -q numpy opencv-contrib-python-headless
fi
mkdir -p "$OUT"
"$VENV/bin/python" bench/depth_edges_bench.py "$RELIEF" "$BUILD/bench/depth_bench_tool" "$DATA" \
  "$OUT" "$@"
