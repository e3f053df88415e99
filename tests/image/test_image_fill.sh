#!/usr/bin/env bash
# relief image-fill from the command line: a fill on a real texture whose
# pixels outside the hole come back unchanged, transparent holes, 16-bit
# images, the report, identical backends, and every bad input of issue 19,
# each with its exit status, its message and no output left behind.
#   test_image_fill.sh PATH/TO/relief PATH/TO/image_tool IMAGES_DIR
set -u
relief=$1 tool=$2 images=$3
tmp=$(mktemp -d /tmp/relief-image-fill-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

. "$(dirname "$0")/../cli/expect.sh" # expect, ok

brick=$images/brick.png
if [[ ! -f $brick ]]; then echo "$brick not found: skipped"; exit 77; fi
"$tool" mask "$tmp/m.png" 512 512 224 224 64 64 || exit 2

# A fill: exit 0, the pixels outside the hole unchanged, the report.
expect 0 "4096 hole pixels" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" -o "$tmp/f.png" --report "$tmp/r.json" --backend scalar
expect 0 "0 values differ outside the hole" -- "$tool" outside "$brick" "$tmp/f.png" "$tmp/m.png"
ok 'grep -q "\"by_copy\": 4096" "$tmp/r.json" && grep -q "\"method\": \"wexler\"" "$tmp/r.json" && grep -q "\"em_steps\": [1-9]" "$tmp/r.json"' "report lacks counts, method or steps"
# Paper 004's method kept: its pyramid of 3 levels over brick.png.
expect 0 "copied" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" -o "$tmp/j.png" --report "$tmp/rj.json" --backend scalar --method jain
ok 'grep -q "\"pyramid_levels\": 3" "$tmp/rj.json" && grep -q "\"method\": \"jain\"" "$tmp/rj.json"' "jain's report lacks its levels"
ok 'grep -q "\"interp_roughness\"" "$tmp/r.json"' "report lacks the 1-D pass's roughness limit"
# The OpenCL backend gives the same bytes (when a device runs).
if "$relief" devices >/dev/null 2>&1 && [[ -n $("$relief" devices 2>/dev/null | grep -i "cpu\|gpu") ]]; then
  expect 0 "" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" -o "$tmp/f_cl.png" --backend opencl --quiet
  ok 'cmp -s "$tmp/f.png" "$tmp/f_cl.png"' "OpenCL and scalar outputs differ"
fi
# The host's threads, and auto (which takes them), give the same bytes and
# say so.
expect 0 "on host (" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" -o "$tmp/f_host.png" --backend host
ok 'cmp -s "$tmp/f.png" "$tmp/f_host.png"' "host and scalar outputs differ"
expect 0 "backend auto: the host's threads" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" -o "$tmp/f_auto.png"
ok 'cmp -s "$tmp/f.png" "$tmp/f_auto.png"' "auto and scalar outputs differ"
# The same seed, the same bytes; the JPEG writer.
expect 0 "" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" -o "$tmp/f2.png" --backend scalar --quiet
ok 'cmp -s "$tmp/f.png" "$tmp/f2.png"' "two runs differ"
"$tool" mask "$tmp/rm.png" 640 427 300 200 30 20 || exit 2
expect 0 "" -- "$relief" image-fill "$images/rocket.jpg" --mask "$tmp/rm.png" -o "$tmp/rocket.jpg" --quiet --backend scalar

# A transparent hole (RGBA, no --mask): filled and opaque; at 16 bits too.
"$tool" rgba "$images/chelsea.png" "$tmp/rgba.png" 200 100 24 24 || exit 2
expect 0 "576 hole pixels" -- "$relief" image-fill "$tmp/rgba.png" -o "$tmp/rgba_f.png" --backend scalar
expect 0 "" -- "$tool" opaque "$tmp/rgba_f.png"
"$tool" deep "$tmp/rgba.png" "$tmp/deep.png" || exit 2
expect 0 "576 hole pixels" -- "$relief" image-fill "$tmp/deep.png" -o "$tmp/deep_f.png" --backend scalar
expect 1 "JPEG holds 8" -- "$relief" image-fill "$tmp/deep.png" -o "$tmp/deep_f.jpg"
ok '[[ ! -e $tmp/deep_f.jpg ]]' "a 16-bit JPEG was left"

# Nothing to fill: the image unchanged, said so.
"$tool" mask "$tmp/zero.png" 512 512 0 0 0 0 || exit 2
expect 0 "no hole pixels" -- "$relief" image-fill "$brick" --mask "$tmp/zero.png" -o "$tmp/z.png"
expect 0 "0 values differ outside the hole" -- "$tool" outside "$brick" "$tmp/z.png" "$tmp/zero.png"

# Bad input: exit 1, a message naming what is wrong, no output.
bad() { # NEEDLE ARGS...
  local needle=$1; shift
  rm -f "$tmp/bad.png"
  expect 1 "$needle" -- "$relief" image-fill "$@" -o "$tmp/bad.png"
  ok '[[ ! -e $tmp/bad.png ]]' "output left after: $*"
}
bad "cannot open" "$tmp/missing.png" --mask "$tmp/m.png"
head -c 3000 "$brick" > "$tmp/trunc.png"
bad "malformed PNG" "$tmp/trunc.png" --mask "$tmp/m.png"
head -c 20000 "$images/rocket.jpg" > "$tmp/trunc.jpg"
bad "truncated JPEG" "$tmp/trunc.jpg" --mask "$tmp/m.png"
echo "not an image" > "$tmp/text.png"
bad "not a PNG, JPEG or binary PNM" "$tmp/text.png" --mask "$tmp/m.png"
: > "$tmp/empty.png"
bad "empty" "$tmp/empty.png" --mask "$tmp/m.png"
bad "malformed PNG" "$brick" --mask "$tmp/trunc.png"
"$tool" mask "$tmp/small.png" 100 100 10 10 5 5 || exit 2
bad "same size" "$brick" --mask "$tmp/small.png"
"$tool" mask "$tmp/all.png" 512 512 0 0 512 512 || exit 2
bad "every pixel" "$brick" --mask "$tmp/all.png"
bad "larger than the image" "$brick" --mask "$tmp/m.png" --window 1025
bad "no alpha channel" "$brick"
bad "expected" "$brick" --mask "$tmp/m.png" --window 2
bad "is not one of" "$brick" --mask "$tmp/m.png" --backend cuda
rm -f "$tmp/bad.png"
expect 2 "over the limit" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" --max-memory 100K -o "$tmp/bad.png"
ok '[[ ! -e $tmp/bad.png ]]' "output left after a refusal for memory"
bad "out of range" "$brick" --mask "$tmp/m.png" --tau -1
cp "$brick" "$tmp/in.png"
expect 1 "never overwrites" -- "$relief" image-fill "$tmp/in.png" --mask "$tmp/m.png" -o "$tmp/in.png"
ok 'cmp -s "$brick" "$tmp/in.png"' "the input was changed"
expect 1 "does not end in" -- "$relief" image-fill "$brick" --mask "$tmp/m.png" -o "$tmp/x.bmp"

echo "test_image_fill: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
