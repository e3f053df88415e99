#!/usr/bin/env bash
# Threads (issue 60): every engine command takes --threads N, and by
# default runs on the CPUs it may run on (its affinity: under `taskset -c 0`
# one thread, where it used to start one per online processor). Each engine
# gives the same bytes on 1 thread, on 3 (more than this machine may have),
# under taskset -c 0 and by default.
#   test_threads.sh PATH/TO/relief PATH/TO/image_tool PATH/TO/test_api_occluders
set -u
relief=$1 itool=$2 occ_tool=$3
tmp=$(mktemp -d /tmp/relief-threads-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
. "$(dirname "$0")/expect.sh" # expect, ok

in=$tmp/in
mkdir "$in"
"$relief" synth plane-waves -o "$in/pw.ply" --vertices 500 --colour 2>/dev/null
"$relief" synth sphere-dimples -o "$in/sd.ply" --vertices 800 2>/dev/null
"$relief" render "$in/pw.ply" -o "$in/img.png" --size 96x64 2>/dev/null
"$itool" mask "$in/mask.png" 96 64 40 25 10 8
# A 64 x 48 organised PCD with a 9 x 6 hole: rows enough for 3 threads in
# the depth repair's ROF (16 rows a share).
{ printf 'VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 64\nHEIGHT 48\n'
  printf 'VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3072\nDATA ascii\n'
  for ((y = 0; y < 48; y++)); do for ((x = 0; x < 64; x++)); do
    if ((x >= 28 && x < 37 && y >= 20 && y < 26)); then echo "nan nan nan"; continue; fi
    z=$((100 + (x * x + 3 * y) % 11)); echo "$(((x - 32) * z))e-3 $(((y - 24) * z))e-3 ${z}e-2"
  done; done; } > "$in/f.pcd"
"$occ_tool" --write "$in" >/dev/null || { echo "FAIL: cannot write the RGB-D frame"; exit 1; }

have_taskset=0
taskset -c 0 true 2>/dev/null && have_taskset=1

# same NAME EXT ARGS...: the command (OUT after -o) by default, with
# --threads 1 and 3, and under taskset -c 0, all the same bytes.
same() {
  local name=$1 ext=$2; shift 2
  expect 0 "" -- "$relief" "$@" -o "$tmp/$name.default$ext" --quiet
  for t in 1 3; do
    expect 0 "" -- "$relief" "$@" -o "$tmp/$name.$t$ext" --threads "$t" --quiet
    ok 'cmp -s "$tmp/$name.default$ext" "$tmp/$name.$t$ext"' "$name: --threads $t gave other bytes than the default"
  done
  if ((have_taskset)); then
    expect 0 "" -- taskset -c 0 "$relief" "$@" -o "$tmp/$name.taskset$ext" --quiet
    ok 'cmp -s "$tmp/$name.default$ext" "$tmp/$name.taskset$ext"' "$name: taskset -c 0 gave other bytes than the default"
  fi
}

same complete .ply complete "$in/pw.ply"
same smooth .ply smooth "$in/pw.ply"
same image-fill .png image-fill "$in/img.png" --mask "$in/mask.png" --window 9
same depth-fill .pcd depth-fill "$in/f.pcd"
same depth-fill-mesh .ply depth-fill "$in/sd.ply" --resolution 24 --solid
same complete-points .ply complete-points "$in/pw.ply" --iterations 2 --max-hole 1000
same remove-occluders .pcd remove-occluders "$in/scene.pcd"

# The threads a run took, as the commands say them: one under taskset -c 0
# (before: one per online processor) and with --threads 1.
if ((have_taskset)); then
  expect 0 "host (1 thread" -- taskset -c 0 "$relief" complete "$in/pw.ply" -o "$tmp/c.ply" --backend host
  expect 0 "on host (1 thread)" -- taskset -c 0 "$relief" image-fill "$in/img.png" --mask "$in/mask.png" -o "$tmp/i.png" --backend host
fi
expect 0 "host (1 thread" -- "$relief" complete "$in/pw.ply" -o "$tmp/c.ply" --backend host --threads 1
expect 0 "on host (3 threads)" -- "$relief" image-fill "$in/img.png" --mask "$in/mask.png" -o "$tmp/i.png" --backend host --threads 3
expect 1 "threads 65 out of range: expected 1..64" -- "$relief" depth-fill "$in/f.pcd" -o "$tmp/d.pcd" --threads 65

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
