#!/usr/bin/env bash
# The GIMP plug-in headless (issue 41): GIMP 2.10 in batch mode (gimp -i -b)
# opens the brick photograph, selects a rectangle, runs
# plug-in-relief-heal-selection non-interactively and saves. The pixels
# outside the selection are unchanged, and the result is the bytes
# `relief image-fill` gives for the same mask, window and seed; the same
# image made RGB with alpha at 16 bits is healed inside the selection
# only. With nothing selected the procedure fails, saying so. GIMP reads its plug-ins from a
# folder of this test's own (GIMP2_DIRECTORY), never the user's.
#   test_gimp.sh PLUGIN RELIEF IMAGE_TOOL DATA_DIR
set -u
plugin=$1 relief=$2 image_tool=$3 data=$4
command -v gimp >/dev/null || { echo "gimp is not installed (setup.sh installs it): skipped"; exit 77; }
brick=$data/images/brick.png
[[ -f $brick ]] || { echo "$brick not found: skipped"; exit 77; }
tmp=$(mktemp -d /tmp/relief-gimp-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
. "$(dirname "$0")/../cli/expect.sh" # ok

export GIMP2_DIRECTORY=$tmp/gimp
mkdir -p "$GIMP2_DIRECTORY/plug-ins/relief-heal-selection"
cp "$plugin" "$GIMP2_DIRECTORY/plug-ins/relief-heal-selection/" || exit 1
cp "$brick" "$tmp/in.png"
"$image_tool" mask "$tmp/mask.png" 512 512 200 240 40 28
"$image_tool" mask "$tmp/none.png" 512 512 0 0 0 0
"$relief" image-fill "$tmp/in.png" --mask "$tmp/mask.png" -o "$tmp/cli.png" --window 17 --seed 3 --quiet

heal='(let* ((image (car (gimp-file-load RUN-NONINTERACTIVE "'$tmp'/in.png" "in.png")))
              (drawable (car (gimp-image-get-active-drawable image))))
         (SELECT)
         (plug-in-relief-heal-selection RUN-NONINTERACTIVE image drawable 17 3)
         (gimp-file-save RUN-NONINTERACTIVE image drawable "'$tmp'/OUT.png" "OUT.png")
         (gimp-image-delete image))'
run_heal() { # run_heal SELECT-EXPRESSION OUT-NAME
  local s=${heal//(SELECT)/$1}
  timeout 300 gimp -i -d -f -b "${s//OUT/$2}" -b '(gimp-quit 0)' > "$tmp/gimp.log" 2>&1
}
run_heal '(gimp-image-select-rectangle image CHANNEL-OP-REPLACE 200 240 40 28)' healed
ok '[[ -f $tmp/healed.png ]]' "GIMP wrote no output: $(tail -3 "$tmp/gimp.log")"
ok '! grep -q "leaked" "$tmp/gimp.log"' "the plug-in leaked: $(grep leaked "$tmp/gimp.log")"
ok '"$image_tool" outside "$tmp/healed.png" "$tmp/in.png" "$tmp/mask.png" >/dev/null' "pixels outside the selection changed"
ok '"$image_tool" outside "$tmp/healed.png" "$tmp/cli.png" "$tmp/none.png" >/dev/null' "the plug-in's fill differs from relief image-fill's: $("$image_tool" outside "$tmp/healed.png" "$tmp/cli.png" "$tmp/mask.png" 2>&1)"
ok '! "$image_tool" outside "$tmp/healed.png" "$tmp/in.png" "$tmp/none.png" >/dev/null 2>&1' "the selection was not filled (the output is the input)"
# RGB with alpha at 16 bits: the brick converted in GIMP, healed, saved as
# a 16-bit RGBA PNG; against the same conversion saved unhealed.
convert='(gimp-image-convert-rgb image) (gimp-image-convert-precision image PRECISION-U16-GAMMA)
         (gimp-layer-add-alpha drawable)
         (gimp-image-select-rectangle image CHANNEL-OP-REPLACE 200 240 40 28)'
run_heal "$convert" deep
conv=${heal//(SELECT)/$convert}
conv=${conv//(plug-in-relief-heal-selection RUN-NONINTERACTIVE image drawable 17 3)/}
timeout 300 gimp -i -d -f -b "${conv//OUT/conv}" -b '(gimp-quit 0)' > "$tmp/gimp2.log" 2>&1
ok 'file "$tmp/deep.png" | grep -q "16-bit/color RGBA" && file "$tmp/conv.png" | grep -q "16-bit/color RGBA"' "16-bit RGBA: $(file "$tmp/deep.png" "$tmp/conv.png" | tr '\n' ' ')"
ok '"$image_tool" outside "$tmp/deep.png" "$tmp/conv.png" "$tmp/mask.png" >/dev/null' "16-bit RGBA: pixels outside the selection changed"
ok '! "$image_tool" outside "$tmp/deep.png" "$tmp/conv.png" "$tmp/none.png" >/dev/null 2>&1' "16-bit RGBA: the selection was not filled"
run_heal '(gimp-selection-none image)' unhealed
ok 'grep -q "nothing is selected" "$tmp/gimp.log" && [[ ! -f $tmp/unhealed.png ]]' "no selection: no clear failure: $(grep -i relief "$tmp/gimp.log" | head -2)"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
