#!/usr/bin/env bash
# Occluders on every shared RGB-D frame (issue 63): `relief occluders` on
# the living-room sequence's five frames, NYU's basement, SUN's corridor and
# office1.pcd, then `relief remove-occluders` with the mask found. Prints a
# table per frame (the mask's share, each background plane's marked share,
# the median seconds of --repeat runs, placeholder pixels left in the
# removed) and writes bench/figures/occluders_<frame>_{before,mask,after}.png.
#   bench/occluders.sh [--repeat N] [BUILD_DIR] [DATA_DIR] [-- relief options...]
# Needs bench/.venv-image (numpy, OpenCV).
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
repeat=3
if [[ ${1:-} == --repeat ]]; then repeat=$2; shift 2; fi
build=$src/build data=$src/../shared/data
if [[ $# -gt 0 && $1 != -- ]]; then build=$1; shift; fi
if [[ $# -gt 0 && $1 != -- ]]; then data=$1; shift; fi
[[ ${1:-} == -- ]] && shift
py=$src/bench/.venv-image/bin/python
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$py" "$src/bench/occluders.py" "$build/relief" "$data" "$src/bench/figures" "$tmp" "$repeat" "$@"
