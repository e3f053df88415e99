#!/usr/bin/env bash
# relief occluders and relief remove-occluders from the command line (issue
# 43): the synthetic RGB-D frame of test_api_occluders (truth known) as an
# organised PCD and as a colour and depth PNG pair, office1.pcd (a real
# Kinect frame), and the bad inputs: one line, exit 1, no output, nothing
# touched.
#   test_occluders.sh RELIEF TEST_API_OCCLUDERS DEPTH_DATA_DIR
set -u
relief=$1 tool=$2 data=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
. "$(dirname "$0")/../cli/expect.sh"

"$tool" --write "$tmp" || { echo "FAIL: cannot write the synthetic frame"; exit 1; }
iou() { "$tool" --iou "$1" "$tmp/truth.png"; }
at_least() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a >= b) }'; }

# The organised PCD: the mask, its report and overlay; IoU against the truth.
expect 0 "2 planes" -- "$relief" occluders "$tmp/scene.pcd" -o "$tmp/m.png" \
  --report "$tmp/r.json" --overlay "$tmp/o.png"
v=$(iou "$tmp/m.png"); echo "scene.pcd: IoU $v"
ok 'at_least "$v" 0.9' "scene.pcd: IoU $v under 0.9"
ok 'grep -q "\"occluder_pixels\"" "$tmp/r.json" && grep -q "\"planes\"" "$tmp/r.json"' \
  "the report lacks its counts"
ok '[[ -s $tmp/o.png ]]' "no overlay"
# The colour image with its depth image (default intrinsics: the frame's).
expect 0 "" -- "$relief" occluders "$tmp/colour.png" --depth "$tmp/depth.png" -o "$tmp/m2.png" --quiet
v=$(iou "$tmp/m2.png"); echo "colour.png + depth.png: IoU $v"
ok 'at_least "$v" 0.9' "colour and depth: IoU $v under 0.9"
# The same pair as binary Netpbm (a P6 and a big-endian 16-bit P5): the same mask.
expect 0 "" -- "$relief" occluders "$tmp/colour.ppm" --depth "$tmp/depth.pgm" -o "$tmp/m3.png" --quiet
ok 'cmp -s "$tmp/m2.png" "$tmp/m3.png"' "colour.ppm + depth.pgm: another mask than the PNG pair"
expect 0 "" -- "$relief" occluders "$tmp/colour.ppm" --depth "$tmp/depth.pgm" --depth-format pgm \
  -o "$tmp/m4.png" --quiet
ok 'cmp -s "$tmp/m2.png" "$tmp/m4.png"' "--depth-format pgm: another mask than auto"
# A given background plane count of one: the floor's points then stand in
# front of the wall, so the mask grows (marking more, never less).
expect 0 "1 plane " -- "$relief" occluders "$tmp/scene.pcd" -o "$tmp/m1.png" --background plane

# The background given as a mesh: the wall and the floor the frame was made of.
printf 'OFF\n8 4 0\n-5 -5 2.25\n5 -5 3.75\n5 0.9 3.75\n-5 0.9 2.25\n-5 0.9 0.5\n5 0.9 0.5\n5 0.9 3.75\n-5 0.9 2.25\n3 0 1 2\n3 0 2 3\n3 4 6 5\n3 4 7 6\n' > "$tmp/bg.off"
expect 0 "background: the mesh" -- "$relief" occluders "$tmp/scene.pcd" -o "$tmp/mm.png" \
  --background-mesh "$tmp/bg.off"
v=$(iou "$tmp/mm.png"); echo "scene.pcd, --background-mesh: IoU $v"
ok 'at_least "$v" 0.9' "--background-mesh: IoU $v under 0.9"

# Neighbouring views (eq. 2.1): a box dark to the depth camera is found by
# its parallax; the same mask from the command line as through the API.
expect 0 "2 views" -- "$relief" occluders "$tmp/dark.pcd" -o "$tmp/dv.png" \
  --views "$tmp/left.png,$tmp/right.png" --poses "$tmp/poses.txt"
expect 0 "" -- "$relief" occluders "$tmp/dark.pcd" -o "$tmp/d0.png" --quiet
v=$(iou "$tmp/dv.png") v0=$(iou "$tmp/d0.png"); echo "dark.pcd: IoU $v0 without views, $v with"
ok 'at_least "$v" "$(awk -v a="$v0" "BEGIN { print a + 0.05 }")"' "views: IoU $v, without $v0"

# The removal: the PCD, its points and pictures; the input untouched.
sum=$(md5sum < "$tmp/scene.pcd")
expect 0 "given the background's depth" -- "$relief" remove-occluders "$tmp/scene.pcd" \
  -o "$tmp/out.pcd" --points "$tmp/p.ply" --occluders "$tmp/used.png" --colour-out "$tmp/c.png" \
  --report "$tmp/rr.json"
ok '[[ $(md5sum < "$tmp/scene.pcd") == "$sum" ]]' "the input changed"
ok 'cmp -s "$tmp/used.png" "$tmp/m.png"' "remove-occluders used another mask than occluders"
ok 'grep -q "property uchar label" "$tmp/p.ply"' "the points have no label"
# The same with the mask given, and for the PNG pair.
expect 0 "" -- "$relief" remove-occluders "$tmp/scene.pcd" -o "$tmp/out2.pcd" --mask "$tmp/m.png" --quiet
ok 'cmp -s "$tmp/out.pcd" "$tmp/out2.pcd"' "a given mask (the found one) gave other bytes"
# Paper 004's colour fill kept by name (issue 62): other bytes than the default's.
expect 0 "" -- "$relief" remove-occluders "$tmp/scene.pcd" -o "$tmp/out3.pcd" --mask "$tmp/m.png" --fill-method jain --quiet
ok '! cmp -s "$tmp/out.pcd" "$tmp/out3.pcd"' "--fill-method jain gave the default's bytes"
expect 0 "" -- "$relief" remove-occluders "$tmp/colour.png" --depth "$tmp/depth.png" \
  -o "$tmp/c2.png" --depth-out "$tmp/d2.png" --quiet

# office1: a real frame (its removal, 5 s here and half a minute under the
# sanitizers, in the default pass only: the synthetic removals above run the
# same code in both).
if [[ -f $data/office1.pcd ]]; then
  expect 0 "3 planes" -- "$relief" occluders "$data/office1.pcd" -o "$tmp/office.png"
  if [[ ${RELIEF_TEST_PASS:-} != sanitize ]]; then
    expect 0 "" -- "$relief" remove-occluders "$data/office1.pcd" -o "$tmp/office.pcd" --quiet
  fi
fi

# Bad input: one line, exit 1, no output.
bad() { # NEEDLE -- ARGS: exit 1, NEEDLE said, no $tmp/bad.*
  local needle=$1; shift 2
  expect 1 "$needle" -- "$relief" "$@"
  ok '! ls "$tmp"/bad.* >/dev/null 2>&1' "an output was written by: $*"
  ok '[[ $(wc -l < "$tmp/err") -le 2 ]]' "more than one line for: $*"
}
bad "no colour" -- occluders "$tmp/nocolour.pcd" -o "$tmp/bad.png"
bad "nothing in front" -- occluders "$tmp/flat.pcd" -o "$tmp/bad.png"
bad "no background found" -- occluders "$tmp/noise.pcd" -o "$tmp/bad.png"
bad "same size" -- occluders "$tmp/colour.png" --depth "$tmp/half.png" -o "$tmp/bad.png"
bad "give its depth" -- occluders "$tmp/colour.png" -o "$tmp/bad.png"
bad "a PCD carries its own depth" -- occluders "$tmp/scene.pcd" --depth "$tmp/depth.png" -o "$tmp/bad.png"
bad "give --depth" -- occluders "$tmp/scene.pcd" -o "$tmp/bad.png" --depth-format nyu
bad "expects a binary PGM" -- occluders "$tmp/colour.png" --depth "$tmp/depth.png" \
  --depth-format nyu -o "$tmp/bad.png"
bad "--depth-format" -- occluders "$tmp/colour.png" --depth "$tmp/depth.png" \
  --depth-format kinect -o "$tmp/bad.png"
bad "--seeding" -- occluders "$tmp/scene.pcd" -o "$tmp/bad.png" --seeding canny
bad "the mask is a PNG" -- occluders "$tmp/scene.pcd" -o "$tmp/bad.jpg"
bad "window" -- occluders "$tmp/scene.pcd" -o "$tmp/bad.png" --window 60
bad "margin" -- occluders "$tmp/scene.pcd" -o "$tmp/bad.png" --margin nan
bad "background-mesh" -- occluders "$tmp/scene.pcd" -o "$tmp/bad.png" --background mesh
bad "" -- occluders "$tmp/missing.pcd" -o "$tmp/bad.png"
bad "" -- occluders "$tmp/scene.pcd" -o "$tmp"
bad "" -- remove-occluders "$tmp/scene.pcd" -o "$tmp/scene.pcd"
bad "--depth-out" -- remove-occluders "$tmp/colour.png" --depth "$tmp/depth.png" -o "$tmp/bad.png"
bad "--fill-method" -- remove-occluders "$tmp/scene.pcd" -o "$tmp/bad.pcd" --fill-method paper
bad "nothing to remove" -- remove-occluders "$tmp/scene.pcd" -o "$tmp/bad.pcd" --mask "$tmp/empty.png"
printf 'VERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 4\nHEIGHT 4\nPOINTS 16\nDATA binary\n' > "$tmp/short.pcd"
bad "" -- occluders "$tmp/short.pcd" -o "$tmp/bad.png"
bad "--views and --poses" -- occluders "$tmp/dark.pcd" -o "$tmp/bad.png" --views "$tmp/left.png"
printf '1 0 0 0.1 0 1 0 0 0 0 1\n1 0 0 -0.1 0 1 0 0 0 0 1 0\n' > "$tmp/short_poses.txt"
bad "line 1: expected 12 numbers" -- occluders "$tmp/dark.pcd" -o "$tmp/bad.png" \
  --views "$tmp/left.png,$tmp/right.png" --poses "$tmp/short_poses.txt"
bad "1 poses for 2 views" -- occluders "$tmp/dark.pcd" -o "$tmp/bad.png" \
  --views "$tmp/left.png,$tmp/right.png" --poses <(head -2 "$tmp/poses.txt")
bad "same size" -- occluders "$tmp/dark.pcd" -o "$tmp/bad.png" --views "$tmp/half.png" \
  --poses <(sed -n 2p "$tmp/poses.txt")
bad "no colour" -- occluders "$tmp/dark.pcd" -o "$tmp/bad.png" --views "$tmp/nocolour.pcd" \
  --poses <(sed -n 2p "$tmp/poses.txt")
# An existing output stays as it was when the run fails.
cp "$tmp/m.png" "$tmp/keep.png"
expect 1 "" -- "$relief" occluders "$tmp/flat.pcd" -o "$tmp/keep.png"
ok 'cmp -s "$tmp/keep.png" "$tmp/m.png"' "a failed run touched an existing output"

echo "test_occluders: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
