#!/usr/bin/env bash
# relief depth-fill from the command line: the real frames (a crop of the
# office PCD with colour, the Middlebury PFM, a 16-bit PNG made from the
# office frame) repaired with their known pixels unchanged and the margin
# outside the capture left missing; measures against a truth; the points;
# the report; identical backends; every bad input of issue 20, each with
# its exit status, its message and no output left behind.
#   test_depth_fill.sh PATH/TO/relief PATH/TO/depth_tool PATH/TO/image_tool DEPTH_DIR
set -u
relief=$1 tool=$2 itool=$3 depth=$4
tmp=$(mktemp -d /tmp/relief-depth-fill-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

. "$(dirname "$0")/../cli/expect.sh" # expect, ok

office=$depth/office1.pcd moto=$depth/motorcycle_disp.pfm
if [[ ! -f $office || ! -f $moto ]]; then echo "$depth: frames not found: skipped"; exit 77; fi
# A 240 x 180 crop of the office frame with its margin (top-left corner),
# and a disc cut from its valid wall, whose truth is the crop itself.
"$tool" crop "$office" 0 0 240 180 "$tmp/office.pcd" || exit 2
"$itool" mask "$tmp/m.png" 240 180 150 100 20 16 || exit 2

# Each variant: exit 0, known pixels unchanged, the report, the measures.
for v in plain haar decompose; do
  expect 0 "variant $v" -- "$relief" depth-fill "$tmp/office.pcd" --mask "$tmp/m.png" --truth "$tmp/office.pcd" -o "$tmp/o_$v.pcd" --variant $v --report "$tmp/r_$v.json" --backend scalar
  expect 0 "0 known differ" -- "$tool" same "$tmp/office.pcd" "$tmp/o_$v.pcd" "$tmp/m.png"
  ok 'grep -q "\"rms\"" "$tmp/r_$v.json" && grep -q "\"variant\": \"'$v'\"" "$tmp/r_$v.json"' "report $v lacks the measures"
done
# The host's threads (auto takes them) give each variant's scalar bytes.
for v in plain haar decompose; do
  expect 0 "on host (" -- "$relief" depth-fill "$tmp/office.pcd" --mask "$tmp/m.png" -o "$tmp/o_${v}_host.pcd" --variant $v --backend host
  ok 'cmp -s "$tmp/o_$v.pcd" "$tmp/o_${v}_host.pcd"' "variant $v: host and scalar outputs differ"
done
# The rim blend is on by default and reported; --no-seam turns it off
# (another fill of the disc, the known pixels still untouched).
ok 'grep -q "\"seam\": true" "$tmp/r_decompose.json" && grep -q "\"seam_edges\": [1-9]" "$tmp/r_decompose.json"' "the report lacks the seam"
expect 0 "" -- "$relief" depth-fill "$tmp/office.pcd" --mask "$tmp/m.png" -o "$tmp/o_ns.pcd" --no-seam --report "$tmp/r_ns.json" --backend scalar --quiet
ok 'grep -q "\"seam\": false" "$tmp/r_ns.json" && grep -q "\"seam_edges\": 0" "$tmp/r_ns.json" && ! cmp -s "$tmp/o_ns.pcd" "$tmp/o_decompose.pcd"' "--no-seam did not turn the blend off"
expect 0 "0 known differ" -- "$tool" same "$tmp/office.pcd" "$tmp/o_ns.pcd" "$tmp/m.png"
# The margin outside the capture stays missing and is reported.
ok 'grep -q "\"outside_left_missing\": [1-9]" "$tmp/r_plain.json"' "the margin was not reported as outside"
expect 0 "outside the capture left missing" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/o.pcd" --variant plain --backend scalar
# The points: a PLY with colour and labels.
expect 0 "" -- "$relief" depth-fill "$tmp/office.pcd" --mask "$tmp/m.png" -o "$tmp/o2.pcd" --points "$tmp/p.ply" --variant plain --quiet --backend scalar
ok 'head -c 400 "$tmp/p.ply" | grep -q "property uchar label" && head -c 400 "$tmp/p.ply" | grep -q "property uchar red"' "points lack colour or labels"
# Same seed, same bytes; OpenCL gives the same bytes when a device runs.
ok 'cmp -s "$tmp/o_plain.pcd" "$tmp/o2.pcd"' "two runs differ"
if "$relief" devices >/dev/null 2>&1 && [[ -n $("$relief" devices 2>/dev/null | grep -i "cpu\|gpu") ]]; then
  # RELIEF_OPENCL_PROFILE=1: where the device's time went, on stderr
  # whatever --quiet says; the same bytes.
  expect 0 "OpenCL profile of the image and depth scorer on" -- env RELIEF_OPENCL_PROFILE=1 "$relief" depth-fill "$tmp/office.pcd" --mask "$tmp/m.png" -o "$tmp/o_cl.pcd" --variant plain --backend opencl --quiet
  ok 'cmp -s "$tmp/o_plain.pcd" "$tmp/o_cl.pcd"' "OpenCL and scalar outputs differ"
  ok 'grep -qE "^relief:   patch_score_rects +[1-9][0-9]* commands +[0-9.]+ s busy" "$tmp/err" && grep -qE "^relief:   read +[1-9][0-9]* commands .* MB$" "$tmp/err"' "the profile lacks the scoring kernel or the read-backs"
  expect 1 "RELIEF_OPENCL_PROFILE='on'" -- env RELIEF_OPENCL_PROFILE=on "$relief" depth-fill "$tmp/office.pcd" --mask "$tmp/m.png" -o "$tmp/o_bad.pcd" --variant plain --backend opencl --quiet
  ok '[[ ! -e $tmp/o_bad.pcd ]]' "output left by a bad RELIEF_OPENCL_PROFILE"
fi
# Waves (--batch): the same bytes on every backend, the known pixels kept,
# the batch reported (out of range: refused below).
expect 0 "" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/o_w.pcd" --variant plain --batch 32 --backend scalar --report "$tmp/r_w.json" --quiet
expect 0 "0 known differ" -- "$tool" same "$tmp/office.pcd" "$tmp/o_w.pcd"
ok 'grep -q "\"batch\": 32" "$tmp/r_w.json" && grep -q "\"batch\": 1," "$tmp/r_plain.json"' "the report lacks the batch"
expect 0 "" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/o_wh.pcd" --variant plain --batch 32 --backend host --quiet
ok 'cmp -s "$tmp/o_w.pcd" "$tmp/o_wh.pcd"' "--batch 32: host and scalar outputs differ"
if "$relief" devices >/dev/null 2>&1 && [[ -n $("$relief" devices 2>/dev/null | grep -i "cpu\|gpu") ]]; then
  expect 0 "" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/o_wcl.pcd" --variant plain --batch 32 --backend opencl --quiet
  ok 'cmp -s "$tmp/o_w.pcd" "$tmp/o_wcl.pcd"' "--batch 32: OpenCL and scalar outputs differ"
fi
# The Middlebury PFM (a crop), and a 16-bit PNG depth image.
"$tool" crop "$moto" 300 200 200 150 "$tmp/moto.pfm" || exit 2
expect 0 "filled" -- "$relief" depth-fill "$tmp/moto.pfm" -o "$tmp/moto_f.pfm" --backend scalar
expect 0 "0 known differ" -- "$tool" same "$tmp/moto.pfm" "$tmp/moto_f.pfm"
"$tool" png16 "$tmp/office.pcd" 5000 "$tmp/office.png" || exit 2
expect 0 "filled" -- "$relief" depth-fill "$tmp/office.png" --mask "$tmp/m.png" -o "$tmp/office_f.png" --backend scalar
expect 0 "0 known differ" -- "$tool" same "$tmp/office.png" "$tmp/office_f.png" "$tmp/m.png"

# A mesh through its six depth images: a hole cut from the Bennu shape
# model, repaired at a low resolution, measured against the whole model.
bennu=$depth/../real/bennu_radar/bennu.obj
if [[ -f $bennu ]]; then
  "$relief" cut "$bennu" -o "$tmp/bennu_cut.ply" --ball 0,0,0.25,0.08 2>/dev/null || exit 2
  expect 0 "voxel IoU" -- "$relief" depth-fill "$tmp/bennu_cut.ply" -o "$tmp/bennu_fix.ply" --resolution 64 --truth "$bennu" --report "$tmp/rm.json" --backend scalar
  ok 'grep -q "\"hausdorff\"" "$tmp/rm.json" && grep -q "\"z_back\"" "$tmp/rm.json"' "the mesh report lacks measures or images"
  expect 2 "lower resolution" -- "$relief" depth-fill "$tmp/bennu_cut.ply" -o "$tmp/bad.ply" --resolution 1024 --max-memory 64M
  ok '[[ ! -e "$tmp/bad.ply" ]]' "a refused mesh left output"
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' > "$tmp/points.obj"
  expect 1 "no triangles" -- "$relief" depth-fill "$tmp/points.obj" -o "$tmp/bad.ply"
  printf 'v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/nan.obj"
  expect 1 "" -- "$relief" depth-fill "$tmp/nan.obj" -o "$tmp/bad.ply"
  ok '[[ ! -e "$tmp/bad.ply" ]]' "a bad mesh left output"
  expect 1 "for depth images" -- "$relief" depth-fill "$tmp/bennu_cut.ply" -o "$tmp/bad.ply" --mask "$tmp/m.png"
fi

# Bad input: exit 1 (2 for resources), the message, no output.
nothing() { ok '[[ ! -e "$tmp/bad.pcd" && ! -e "$tmp/bad.pfm" && ! -e "$tmp/bad.png" && ! -e "$tmp/bad.json" ]]' "output left behind: $1"; }
for b in 0 257; do
  expect 1 "batch" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --batch $b; nothing "--batch $b"
done
expect 1 "a tileable image is filled a pixel at a time" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --batch 4 --tileable; nothing "--batch with --tileable"
head -c 300 "$office" > "$tmp/trunc.pcd"
expect 1 "truncated" -- "$relief" depth-fill "$tmp/trunc.pcd" -o "$tmp/bad.pcd"; nothing truncated
printf 'Pf\n4 4\n-1.0\n' > "$tmp/short.pfm"
expect 1 "PFM truncated" -- "$relief" depth-fill "$tmp/short.pfm" -o "$tmp/bad.pfm"; nothing "short PFM"
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n1 2 3\n4 5 6\n7 8 9\n' > "$tmp/unorg.pcd"
expect 1 "unorganised" -- "$relief" depth-fill "$tmp/unorg.pcd" -o "$tmp/bad.pcd"; nothing unorganised
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA ascii\nnan nan nan\nnan nan nan\nnan nan nan\nnan nan nan\n' > "$tmp/allnan.pcd"
expect 1 "every pixel is missing" -- "$relief" depth-fill "$tmp/allnan.pcd" -o "$tmp/bad.pcd"; nothing "all missing"
"$tool" ring 40 30 "$tmp/ring.pfm" || exit 2
expect 1 "touches every border" -- "$relief" depth-fill "$tmp/ring.pfm" -o "$tmp/bad.pfm"; nothing ring
# On a torus (--tileable) the margin is enclosed: it is filled.
expect 0 "0 outside the capture" -- "$relief" depth-fill "$tmp/ring.pfm" -o "$tmp/ring_t.pfm" --tileable --backend scalar
rm -f "$tmp/ring_t.pfm"
expect 2 "over the limit" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --max-memory 2M; nothing memory
"$itool" mask "$tmp/m2.png" 100 100 10 10 5 5 || exit 2
expect 1 "same size" -- "$relief" depth-fill "$tmp/office.pcd" --mask "$tmp/m2.png" -o "$tmp/bad.pcd"; nothing "mask size"
expect 1 "IN's format" -- "$relief" depth-fill "$tmp/office.pcd" --truth "$tmp/moto.pfm" -o "$tmp/bad.pcd"; nothing "truth format"
expect 1 "cannot" -- "$relief" depth-fill "$tmp/none.pcd" -o "$tmp/bad.pcd"; nothing missing
expect 1 "IN's extension" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pfm"
expect 1 "never overwrites" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/office.pcd"
expect 1 "organised PCD" -- "$relief" depth-fill "$tmp/moto.pfm" -o "$tmp/bad.pfm" --points "$tmp/p2.ply"
expect 1 "odd" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --window 8
expect 1 "not one of plain, haar, decompose" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --variant median
expect 1 "IN's extension" -- "$relief" depth-fill "$tmp/x.ply" -o "$tmp/bad.pcd"
expect 1 "levels 5 leaves" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --variant haar --levels 5; nothing levels
# Depth edges (issue 63): layers by default, reported; across is paper
# 003's; --colour for a PNG's registered colour (any image of its size);
# NYU's raw PGM by --depth-format, written as a 16-bit PNG. The whole
# office frame: a chair, a desk and their shadows on the wall.
"$tool" png16 "$office" 5000 "$tmp/full.png" || exit 2
expect 0 "" -- "$relief" depth-fill "$tmp/full.png" -o "$tmp/e_l.png" --report "$tmp/r_e.json" --quiet
ok 'grep -q "\"edges\": \"layers\"" "$tmp/r_e.json" && grep -q "\"stepped_holes\": [1-9]" "$tmp/r_e.json"' "the report lacks the layers"
expect 0 "" -- "$relief" depth-fill "$tmp/full.png" -o "$tmp/e_a.png" --edges across --quiet
ok '! cmp -s "$tmp/e_l.png" "$tmp/e_a.png"' "edges across gave the layers' bytes"
"$itool" mask "$tmp/c.png" 640 480 0 0 320 480 || exit 2
expect 0 "parted by colour" -- "$relief" depth-fill "$tmp/full.png" -o "$tmp/e_c.png" --colour "$tmp/c.png"
expect 1 "same size" -- "$relief" depth-fill "$tmp/office.png" -o "$tmp/bad.png" --colour "$tmp/m2.png"; nothing "colour size"
expect 1 "carries its own colour" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --colour "$tmp/c.png"; nothing "colour with a PCD"
expect 1 "not one of auto, layers, across" -- "$relief" depth-fill "$tmp/office.png" -o "$tmp/bad.png" --edges ramp; nothing "edges"
nyu=$depth/../rgbd/nyu/NYU_depth.pgm
if [[ -f $nyu ]]; then
  expect 0 "holes across a depth step" -- "$relief" depth-fill "$nyu" --depth-format nyu -o "$tmp/nyu.png"
  expect 1 "16-bit PNG" -- "$relief" depth-fill "$nyu" --depth-format nyu -o "$tmp/bad.pgm"; nothing "PGM out"
fi
expect 1 "no PNG or PGM" -- "$relief" depth-fill "$tmp/office.pcd" --depth-format nyu -o "$tmp/bad.pcd"; nothing "format of a PCD"
# A depth image's points through its camera (--intrinsics numbers or
# Open3D's camera JSON): every pixel, the filled ones labelled 1.
expect 0 "" -- "$relief" depth-fill "$tmp/full.png" -o "$tmp/e_p.png" --intrinsics 525,525,319.5,239.5 --points "$tmp/e_p.ply" --quiet
ok 'grep -aq "element vertex" "$tmp/e_p.ply" && grep -aq "property uchar label" "$tmp/e_p.ply" && cmp -s "$tmp/e_p.png" "$tmp/e_l.png"' "a PNG's points through --intrinsics"
expect 1 "depth image's camera" -- "$relief" depth-fill "$tmp/full.png" -o "$tmp/bad.png" --points "$tmp/bad.ply"; nothing "points without a camera"
expect 1 "a PCD carries its points" -- "$relief" depth-fill "$tmp/office.pcd" -o "$tmp/bad.pcd" --intrinsics 525,525,320,240; nothing "intrinsics with a PCD"
cam=$depth/../rgbd/sequence/camera_primesense.json
if [[ -f $cam ]]; then
  expect 0 "" -- "$relief" depth-fill "$tmp/full.png" -o "$tmp/e_j.png" --intrinsics "$cam" --points "$tmp/e_j.ply" --quiet
  ok 'cmp -s "$tmp/e_j.ply" "$tmp/e_p.ply"' "the camera JSON gave other points than its numbers"
  expect 1 "is a camera of 640 x 480" -- "$relief" depth-fill "$tmp/office.png" -o "$tmp/bad.png" --intrinsics "$cam" --points "$tmp/bad.ply"; nothing "camera size"
fi
ok 'cmp -s "$tmp/office.pcd" <("$tool" crop "$office" 0 0 240 180 "$tmp/again.pcd" && cat "$tmp/again.pcd")' "the input was changed"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
