#!/usr/bin/env bash
# The texture optimisation's grid search three ways, side by side in one
# script (issue 21: "FLANN kd-trees or the OpenCL matcher where it wins;
# measure both"): FLANN's exact kd-tree (the default), brute force on the
# host (the scalar twin, threaded) and brute force by kernels/grid.cl on
# the OpenCL device (PoCL's CPU device here, a GPU where there is one), on
# the cut captures bench/points.sh leaves in OUT (it is run first, without
# Open3D, when they are missing). Prints, per capture, the texture stage's
# and the whole run's median seconds over REPEAT runs, each ratio to the
# kd-tree's, and whether the outputs are the same bytes (brute's two
# backends must be; the kd-tree may differ at near ties).
#   bench/points_search.sh [CAPTURE_NAME ...]   (default: all in OUT)
# Environment: OUT (default bench-out/points), BUILD (default build),
# REPEAT (default 3), DEVICE (an OpenCL device index; default the first).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench-out/points}
BUILD=${BUILD:-build}
REPEAT=${REPEAT:-3}
if ! ls "$OUT"/*_capture.ply >/dev/null 2>&1; then
  bench/points.sh --no-open3d
fi
cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief >/dev/null
names=("$@")
if [[ ${#names[@]} -eq 0 ]]; then
  for f in "$OUT"/*_capture.ply; do names+=("$(basename "$f" _capture.ply)"); done
fi
dev=()
[[ -n ${DEVICE:-} ]] && dev=(--device "$DEVICE")
tmp=$(mktemp -d /tmp/relief-psearch-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf '%-12s %-14s %9s %9s %11s %11s %s\n' case search texture_s total_s tex/kdtree total/kdtree bytes
for name in "${names[@]}"; do
  cap=$OUT/${name}_capture.ply
  for search in kdtree scalar opencl; do
    case $search in
      kdtree) args=() ;;
      scalar) args=(--grid-search brute --backend scalar) ;;
      opencl) args=(--grid-search brute --backend opencl "${dev[@]}") ;;
    esac
    for r in $(seq "$REPEAT"); do
      "$BUILD/relief" complete-points "$cap" -o "$tmp/${name}_$search.ply" "${args[@]}" \
        --report "$tmp/${name}_${search}_$r.json" --quiet
    done
  done
  /usr/bin/python3 - "$tmp" "$name" "$REPEAT" <<'PY'
import json, statistics, sys, filecmp
tmp, name, rep = sys.argv[1], sys.argv[2], int(sys.argv[3])
med = {}
for s in ("kdtree", "scalar", "opencl"):
    runs = [json.load(open(f"{tmp}/{name}_{s}_{r}.json"))["seconds"] for r in range(1, rep + 1)]
    med[s] = (statistics.median(x["texture"] for x in runs), statistics.median(x["total"] for x in runs))
for s in ("kdtree", "scalar", "opencl"):
    same = {"kdtree": "", "scalar": "= kdtree" if filecmp.cmp(f"{tmp}/{name}_scalar.ply", f"{tmp}/{name}_kdtree.ply", shallow=False) else "differs from kdtree",
            "opencl": "= scalar" if filecmp.cmp(f"{tmp}/{name}_opencl.ply", f"{tmp}/{name}_scalar.ply", shallow=False) else "DIFFERS FROM SCALAR"}[s]
    t, T = med[s]
    print("%-12s %-14s %9.2f %9.2f %11.2f %11.2f %s" % (name, {"kdtree": "kd-tree", "scalar": "brute scalar", "opencl": "brute OpenCL"}[s], t, T, t / med["kdtree"][0], T / med["kdtree"][1], same))
PY
done
