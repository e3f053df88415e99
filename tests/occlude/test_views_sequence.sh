#!/usr/bin/env bash
# The views cue (paper 004, eq. 2.1) on a real registered sequence (issue 63,
# ask 4): the shared living room's frame 0 with frames 1..4 as views, their
# poses from Open3D's trajectory log, the camera from its JSON. The views
# should agree with the depth: the points in front of the background judged
# foreground more often than background, those on it background. Also
# --points from the colour + depth pair, and the pose and camera files' bad
# inputs (one line, exit 1, no output).
#   test_views_sequence.sh RELIEF RGBD_DATA_DIR
set -u
relief=$1 seq=$2/sequence
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
. "$(dirname "$0")/../cli/expect.sh"
[[ -f $seq/trajectory.log ]] || { echo "no $seq/trajectory.log: skipped"; exit 77; }

views="$seq/color/00001.jpg,$seq/color/00002.jpg,$seq/color/00003.jpg,$seq/color/00004.jpg"
frame=("$seq/color/00000.jpg" --depth "$seq/depth/00000.png" --scale 1000
       --intrinsics "$seq/camera_primesense.json")
# member A.B of a report (a whole number)
member() { tr -d ' \n' < "$1" | grep -o "\"$2\":{[^}]*}" | grep -o "\"$3\":[0-9]*" | cut -d: -f2; }

# The views are 2.3 to 9.7 cm from the frame: the chair's seat at 1.2 m
# moves up to 18 pixels against the wall behind (--view-radius 24), its
# back 15 cm before the wall under 2 (--parallax 1).
expect 0 "4 views (eq. 2.1)" -- "$relief" occluders "${frame[@]}" -o "$tmp/m.png" \
  --views "$views" --poses "$seq/trajectory.log" --view-radius 24 --parallax 1 \
  --report "$tmp/r.json" --points "$tmp/p.ply"
ff=$(member "$tmp/r.json" in_front foreground) fb=$(member "$tmp/r.json" in_front background)
bb=$(member "$tmp/r.json" on_background background) bf=$(member "$tmp/r.json" on_background foreground)
echo "sequence 0 with views 1..4: in front $ff foreground, $fb background; on the background $bb background, $bf foreground"
ok '[[ -n $ff && $ff -gt $fb ]]' "in front of the background: $ff judged foreground, $fb background"
ok '[[ -n $bb && $bb -gt $((20 * bf)) ]]' "on the background: $bb judged background, $bf foreground"
# The log's entries by order and by --view-index: the same mask.
expect 0 "" -- "$relief" occluders "${frame[@]}" -o "$tmp/m2.png" --views "$views" \
  --poses "$seq/trajectory.log" --view-radius 24 --parallax 1 --frame-index 0 \
  --view-index 1,2,3,4 --quiet
ok 'cmp -s "$tmp/m.png" "$tmp/m2.png"' "--view-index 1,2,3,4: another mask than the entries in order"
# --points from the pair: one vertex per captured pixel, labelled.
ok 'grep -aq "^element vertex 267129$" "$tmp/p.ply" && grep -aq "^property uchar label$" "$tmp/p.ply"' \
  "--points: not the 267129 captured pixels of frame 0 with labels"

# The bad inputs.
bad() { # NEEDLE -- ARGS: exit 1, NEEDLE said, no $tmp/bad.*
  local needle=$1; shift 2
  expect 1 "$needle" -- "$relief" "$@"
  ok '! ls "$tmp"/bad.* >/dev/null 2>&1' "an output was written by: $*"
  ok '[[ $(wc -l < "$tmp/err") -le 2 ]]' "more than one line for: $*"
}
bad "--frame-index 5: --poses" -- occluders "${frame[@]}" -o "$tmp/bad.png" --views "$views" \
  --poses "$seq/trajectory.log" --frame-index 5
bad "--view-index 9 (view 1)" -- occluders "${frame[@]}" -o "$tmp/bad.png" \
  --views "$seq/color/00001.jpg,$seq/color/00002.jpg" --poses "$seq/trajectory.log" --view-index 1,9
bad "--view-index: one entry per view" -- occluders "${frame[@]}" -o "$tmp/bad.png" \
  --views "$views" --poses "$seq/trajectory.log" --view-index 1,2
bad "--frame-index and --view-index pick" -- occluders "${frame[@]}" -o "$tmp/bad.png" \
  --views "$seq/color/00001.jpg" --poses <(echo "1 0 0 0 0 1 0 0 0 0 1 0") --frame-index 1
bad "give --views and --poses" -- occluders "${frame[@]}" -o "$tmp/bad.png" --frame-index 1
head -10 "$seq/trajectory.log" | sed '9s/.*/0.5 0 0 0/' > "$tmp/skew.log"
bad "entry 1 is no rigid motion" -- occluders "${frame[@]}" -o "$tmp/bad.png" \
  --views "$seq/color/00001.jpg" --poses "$tmp/skew.log"
head -8 "$seq/trajectory.log" > "$tmp/cut.log"
bad "entry 1: expected row 3" -- occluders "${frame[@]}" -o "$tmp/bad.png" \
  --views "$seq/color/00001.jpg" --poses "$tmp/cut.log"
sed 's/640/320/' "$seq/camera_primesense.json" > "$tmp/small.json"
bad "is a camera of 320 x 480 pixels" -- occluders "$seq/color/00000.jpg" --depth "$seq/depth/00000.png" \
  --scale 1000 --intrinsics "$tmp/small.json" -o "$tmp/bad.png"
sed 's/525.0,/-525.0,/' "$seq/camera_primesense.json" > "$tmp/neg.json"
bad "is no pinhole camera" -- occluders "$seq/color/00000.jpg" --depth "$seq/depth/00000.png" \
  --scale 1000 --intrinsics "$tmp/neg.json" -o "$tmp/bad.png"
echo '{"width": 640}' > "$tmp/part.json"
bad "height is missing" -- occluders "$seq/color/00000.jpg" --depth "$seq/depth/00000.png" \
  --scale 1000 --intrinsics "$tmp/part.json" -o "$tmp/bad.png"
bad "--view-intrinsics ${tmp}/small.json is a camera of 320 x 480" -- occluders "${frame[@]}" \
  -o "$tmp/bad.png" --views "$seq/color/00001.jpg" --poses "$seq/trajectory.log" \
  --view-intrinsics "$tmp/small.json"

echo "test_views_sequence: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
