#!/usr/bin/env bash
# The same bytes on a GPU: every engine's OpenCL output against its scalar
# reference's, through the library's entry points as the command line calls
# them, on a machine whose OpenCL device is a GPU (the lent device machine;
# on PoCL the suite checks the same). Two steps:
#   tests/cli/gpu_same_bytes.sh stage BUILD_DIR   here: copies the program,
#       the shared libraries it needs that a bare machine lacks, the OpenCL
#       ICD loader and the inputs (made from ../shared/data) into .gpu/
#   tests/cli/gpu_same_bytes.sh run [OUT_DIR]     there: NVIDIA's OpenCL by
#       its ICD, each case twice, cmp, a line per case and a summary
# .gpu/ is ignored (.git/info/exclude); carry it to the device.
set -u
here=$(cd "$(dirname "$0")/../.." && pwd)
stage=$here/.gpu

do_stage() {
  local build=$1 data=$here/../shared/data
  rm -rf "$stage" && mkdir -p "$stage/lib" "$stage/in"
  grep -qx '/.gpu/' "$here/.git/info/exclude" 2>/dev/null || echo '/.gpu/' >> "$here/.git/info/exclude"
  cp "$build/relief" "$stage/"
  ldd "$build/relief" | awk '/=> \// {print $3}' |
    grep -E 'OpenMesh|flann|qhull|png|jpeg|lzf|OpenCL|lz4|hdf5|gomp' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
  "$build/relief" synth cylinder-bark --colour --seed 1 --vertices 1500 -o "$stage/in/bark.ply" 2>/dev/null
  "$build/relief" cut "$data/real/fertility/fertility.off" -o "$stage/in/fert.ply" --ball 5.48,31.18,10.73,8 2>/dev/null
  "$build/tests/image_tool" mask "$stage/in/m.png" 512 512 224 224 48 48
  cp "$data/images/brick.png" "$stage/in/"
  "$build/tests/depth_tool" crop "$data/depth/office1.pcd" 0 0 240 180 "$stage/in/office.pcd"
  "$build/tests/image_tool" mask "$stage/in/dm.png" 240 180 150 100 20 16
  du -sh "$stage"
}

do_run() {
  local out=${1:-/tmp/gpu-same} pass=0 fail=0
  mkdir -p "$out" "$stage/icd"
  # NVIDIA's ICD by its full path: the driver's libraries may lie outside
  # the loader's search path (/usr/local/nvidia/lib64).
  local icd
  icd=$(find / -xdev -name 'libnvidia-opencl.so.1' 2>/dev/null | head -1)
  echo "${icd:-libnvidia-opencl.so.1}" > "$stage/icd/nvidia.icd"
  export OCL_ICD_VENDORS=$stage/icd LD_LIBRARY_PATH=$stage/lib:${LD_LIBRARY_PATH:-}
  local relief=$stage/relief in=$stage/in
  "$relief" devices || { echo "no OpenCL device"; exit 77; }
  case_() { # NAME OUTPUT-EXTENSION ARGS... (the output is -o NAME_BACKEND.EXT)
    local name=$1 ext=$2; shift 2
    for b in scalar opencl; do
      local t0=$(date +%s%N) rc
      "$relief" "$@" -o "$out/${name}_$b.$ext" --backend "$b" --quiet 2> "$out/${name}_$b.err"
      rc=$?
      echo "$name $b: exit $rc, $(( ($(date +%s%N) - t0) / 1000000 )) ms"
    done
    if cmp -s "$out/${name}_scalar.$ext" "$out/${name}_opencl.$ext"; then
      pass=$((pass + 1)); echo "same: $name"
    else
      fail=$((fail + 1)); echo "DIFFERENT: $name"; cat "$out/${name}_opencl.err"
    fi
  }
  case_ complete ply complete "$in/bark.ply"
  case_ complete_levels ply complete "$in/bark.ply" --levels 2
  case_ complete_smooth_base ply complete "$in/fert.ply" --base smooth
  case_ image_fill png image-fill "$in/brick.png" --mask "$in/m.png"
  case_ depth_fill pcd depth-fill "$in/office.pcd" --mask "$in/dm.png"
  case_ depth_fill_plain pcd depth-fill "$in/office.pcd" --mask "$in/dm.png" --variant plain
  case_ points_brute ply complete-points "$in/fert.ply" --iterations 5 --grid-search brute
  echo "gpu_same_bytes: $pass same, $fail different"
  [[ $fail -eq 0 ]]
}

case "${1:-}" in
  stage) do_stage "${2:?usage: $0 stage BUILD_DIR}" ;;
  run) do_run "${2:-}" ;;
  *) echo "usage: $0 stage BUILD_DIR | run [OUT_DIR]" >&2; exit 1 ;;
esac
