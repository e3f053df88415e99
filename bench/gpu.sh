#!/usr/bin/env bash
# Every engine on scalar, host and OpenCL on a machine with a GPU (issue
# 42's table; bench/engines.py says what is measured). Every row, the bark
# included, was about 9 minutes on a 16-core host before the profile runs
# (PROFILE below, about a minute more): split it into two calls under the
# 10 minutes each may take (CASES=1,2,3,4,5,6,7 BARK=0, then CASES=8,9).
# The device machine is bare and builds nothing, so two steps:
#   bench/gpu.sh stage [BUILD_DIR]   here: the programs (relief, bench_complete,
#       image_tool), the shared libraries a bare machine lacks and the
#       inputs (made here from ../shared/data) into .gpu-bench/ (ignored;
#       carry it)
#   bench/gpu.sh run [OUT_DIR]       there: NVIDIA's OpenCL by its ICD, the
#       table (engines.md, engines.csv) in OUT_DIR (default $OUT, else
#       /tmp/gpu-bench), exit 1 when a backend's bytes differ
# Environment for run: REPS (3), CASES (all; e.g. 2,3,4 or image-fill),
# BARK (1: paper 000's bark growth on OpenCL and host; 0 to skip),
# PROFILE (1, the default: each case's OpenCL run once more with
# RELIEF_OPENCL_PROFILE=1, where the device's time goes, kernels against
# transfers against the host: profile.txt, about a minute; 0 to skip),
# NCU (1: Nsight Compute, where the machine has ncu, on the mesh kernel's
# first launches of the demo: ncu.txt; it has seen no OpenCL kernel on
# NVIDIA's driver so far), IMAGEBENCH (1: then
# bench_image_fill, the image filler's OpenCL reading every score back
# against ranking blocks on the device, on the bench's 7 images and the
# atlas, about a minute: image_fill.txt).
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
stage=$here/.gpu-bench

do_stage() {
  local build=$1 data=$here/../shared/data
  rm -rf "$stage" && mkdir -p "$stage/lib" "$stage/data/images" "$stage/data/depth" "$stage/out"
  grep -qx '/.gpu-bench/' "$here/.git/info/exclude" 2>/dev/null ||
    echo '/.gpu-bench/' >> "$here/.git/info/exclude"
  cp "$build/relief" "$build/bench/bench_complete" "$build/bench/bench_image_fill" \
    "$build/tests/image_tool" "$stage/"
  for p in "$build/relief" "$build/bench/bench_complete" "$build/bench/bench_image_fill" \
    "$build/tests/image_tool"; do
    ldd "$p" | awk '/=> \// {print $3}'
  done | sort -u | grep -E 'relief|OpenMesh|flann|qhull|png|jpeg|lzf|OpenCL|lz4|hdf5|gomp' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
  for i in brick.png grass.png gravel.png coffee.png chelsea.png astronaut.png rocket.jpg; do
    cp "$data/images/$i" "$stage/data/images/"
  done
  cp "$data/depth/office1.pcd" "$stage/data/depth/"
  # The inputs engines.py makes, made here (the machine there lacks the
  # scans and the other images).
  python3 "$here/bench/engines.py" "$build/relief" "$build/tests/image_tool" "$data" \
    "$stage/out" --cases none >/dev/null
  cp "$here/bench/engines.py" "$stage/"
  du -sh "$stage"
}

do_run() {
  local out=${1:-${OUT:-/tmp/gpu-bench}} icd
  mkdir -p "$out" "$stage/icd"
  cp -r "$stage/out/in" "$out/" 2>/dev/null
  # NVIDIA's ICD by its full path: the driver's libraries may lie outside
  # the loader's search path (/usr/local/nvidia/lib64).
  icd=$(find / -xdev -name 'libnvidia-opencl.so.1' 2>/dev/null | head -1)
  echo "${icd:-libnvidia-opencl.so.1}" > "$stage/icd/nvidia.icd"
  export OCL_ICD_VENDORS=$stage/icd LD_LIBRARY_PATH=$stage/lib:${LD_LIBRARY_PATH:-}
  "$stage/relief" devices || { echo "gpu.sh: no OpenCL device"; exit 77; }
  nproc; grep -m1 'model name' /proc/cpuinfo; nvidia-smi -L 2>/dev/null
  local bark=()
  [[ ${BARK:-1} == 1 ]] && bark=(--bench-complete "$stage/bench_complete")
  [[ ${PROFILE:-1} == 1 ]] && bark+=(--profile)
  python3 "$stage/engines.py" "$stage/relief" "$stage/image_tool" "$stage/data" "$out" \
    --backends scalar,host,opencl --reps "${REPS:-3}" ${CASES:+--cases "$CASES"} "${bark[@]}"
  local rc=$?
  if [[ ${IMAGEBENCH:-0} == 1 ]]; then
    "$stage/bench_image_fill" "$stage/data/images" --repeat 3 --atlas "$out/in/atlas.png" \
      --atlas-mask "$out/in/atlas_mask.png" > "$out/image_fill.txt" 2>&1 || rc=1
    cat "$out/image_fill.txt"
  fi
  if [[ ${NCU:-0} == 1 ]] && command -v ncu >/dev/null; then
    timeout 240 ncu --target-processes all --launch-count 6 --section SpeedOfLight \
      --section MemoryWorkloadAnalysis --section Occupancy --section WarpStateStats \
      "$stage/relief" complete "$out/in/demo.ply" -o "$out/ncu.ply" --backend opencl --quiet \
      > "$out/ncu.txt" 2>&1
    echo "gpu.sh: ncu exit $?: $(grep -c 'Section: ' "$out/ncu.txt") sections in ncu.txt"
  fi
  return $rc
}

case "${1:-}" in
  stage) do_stage "${2:-build}" ;;
  run) do_run "${2:-}" ;;
  *) echo "usage: $0 stage [BUILD_DIR] | run [OUT_DIR]" >&2; exit 1 ;;
esac
