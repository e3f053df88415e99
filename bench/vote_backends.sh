#!/usr/bin/env bash
# image-fill's patch voting (the default method, issue 62) on its three
# backends side by side: scalar (one thread, the reference), host (every
# core) and OpenCL (PoCL here, a GPU where one is lent), REPS runs each,
# interleaved, the median of the fill's own seconds (the report's
# seconds.total: the call, without the PNG reading and writing) and its
# ratio to scalar;
# exit 1 when a backend's bytes differ from scalar's. Cases: astronaut
# 512 x 512 with a 230 x 230 hole, and a 20-megapixel photograph (astronaut
# and coffee scaled to 5472 x 3648) with a 300 x 300 hole.
#   bench/vote_backends.sh [BUILD_DIR]
# Environment: REPS (3), OUT (default bench/out/vote_backends).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
relief=$build/relief
out=${OUT:-bench/out/vote_backends}
reps=${REPS:-3}
data=../shared/data/images
mkdir -p "$out"
# The project's .venv (./setup.sh python) has OpenCV to make the inputs.
py=${PYTHON:-.venv/bin/python}
"$py" - "$data" "$out" <<'PY'
import sys, os
import cv2, numpy as np
data, out = sys.argv[1], sys.argv[2]
m = np.zeros((512, 512), np.uint8); m[141:371, 141:371] = 255
cv2.imwrite(out + "/astronaut_mask.png", m)
if not os.path.exists(out + "/big.png"):
    a = cv2.resize(cv2.imread(data + "/astronaut.png"), (3648, 3648), interpolation=cv2.INTER_CUBIC)
    c = cv2.resize(cv2.imread(data + "/coffee.png"), (1824, 3648), interpolation=cv2.INTER_CUBIC)
    cv2.imwrite(out + "/big.png", np.hstack([a, c]))
m = np.zeros((3648, 5472), np.uint8); m[1800:2100, 1500:1800] = 255
cv2.imwrite(out + "/big_mask.png", m)
PY
cases=("astronaut $data/astronaut.png $out/astronaut_mask.png"
       "20MP $out/big.png $out/big_mask.png")
status=0
printf "%-10s %-8s %9s %8s %s\n" case backend "fill s" "x scalar" bytes
for c in "${cases[@]}"; do
  read -r name img mask <<<"$c"
  declare -A t=()
  for ((r = 0; r < reps; ++r)); do
    for b in scalar host opencl; do
      "$relief" image-fill "$img" --mask "$mask" -o "$out/${name}_$b.png" --backend "$b" \
        --quiet --report "$out/${name}_$b.json"
      t[$b]+="$("$py" -c 'import json,sys; r=json.load(open(sys.argv[1])); print(r["seconds"]["total"])' "$out/${name}_$b.json") "
    done
  done
  base=$(echo "${t[scalar]}" | tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  for b in scalar host opencl; do
    med=$(echo "${t[$b]}" | tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
    same=same
    cmp -s "$out/${name}_scalar.png" "$out/${name}_$b.png" || { same=DIFFER; status=1; }
    printf "%-10s %-8s %9.3f %8.2f %s\n" "$name" "$b" "$med" "$(echo "$base / $med" | bc -l)" "$same"
  done
  unset t
done
exit $status
