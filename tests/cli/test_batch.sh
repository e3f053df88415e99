#!/usr/bin/env bash
# Several inputs to one command (issue 41, host/cli/batch.h): each output is
# the bytes a run on that input alone gives; a bad input fails alone (exit
# 1, the others written, a summary naming it); what a batch cannot do is
# refused before any run, with nothing written.
#   test_batch.sh PATH/TO/relief PATH/TO/image_tool DATA_DIR
set -u
relief=$1 image_tool=$2 data=$3
tmp=$(mktemp -d /tmp/relief-batch-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
. "$(dirname "$0")/expect.sh" # expect, ok

mkdir -p "$tmp/in" "$tmp/o" "$tmp/one" "$tmp/b"
# 800-vertex captures: a completion of the default 2000 took 9 s under ASan,
# of these 1.5 s.
for i in 1 2; do
  "$relief" synth plane-waves -o "$tmp/in/cap$i.ply" --seed $i --vertices 800 2>/dev/null || exit 2
done
echo "ply garbage" > "$tmp/in/bad.ply"
expect 1 "2 of 3 inputs done" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/bad.ply" "$tmp/in/cap2.ply" -o "$tmp/o/" --backend scalar
ok 'grep -q "failed: $tmp/in/bad.ply (exit 1)" "$tmp/err" && grep -q "\[3/3\]" "$tmp/err"' "the summary does not name the bad input, or the batch stopped at it"
ok '[[ -f $tmp/o/cap1.ply && -f $tmp/o/cap2.ply && ! -e $tmp/o/bad.ply ]]' "the good outputs were not all kept, or the bad one left a file: $(ls "$tmp/o")"
for i in 1 2; do
  "$relief" complete "$tmp/in/cap$i.ply" -o "$tmp/one/cap$i.ply" --backend scalar --quiet
  ok 'cmp -s "$tmp/o/cap$i.ply" "$tmp/one/cap$i.ply"' "cap$i: the batch's output differs from a run on it alone"
done

# image-fill keeps each input's extension; one mask serves every frame.
brick=$data/images/brick.png grass=$data/images/grass.png
if [[ -f $brick && -f $grass ]]; then
  "$image_tool" mask "$tmp/mask.png" 512 512 200 240 30 20
  expect 0 "2 of 2 inputs done" -- "$relief" image-fill "$brick" "$grass" --mask "$tmp/mask.png" -o "$tmp/o" --window 9
  "$relief" image-fill "$grass" --mask "$tmp/mask.png" -o "$tmp/one/grass.png" --window 9 --quiet
  ok 'cmp -s "$tmp/o/grass.png" "$tmp/one/grass.png" && [[ -f $tmp/o/brick.png ]]' "image-fill: the batch's grass.png differs from a run on it alone"
  # What --atlas leaves alone is known from the parse, not from argv's
  # text: --wind 9 is --window 9 (before, --atlas took it for not given).
  "$image_tool" mask "$tmp/small.png" 512 512 200 240 10 10
  expect 0 "" -- "$relief" image-fill "$brick" --mask "$tmp/small.png" -o "$tmp/one/atlas.png" --atlas --wind 9 --report "$tmp/one/atlas.json"
  ok 'grep -q "\"window\": 9," "$tmp/one/atlas.json"' "image-fill --atlas --wind 9: the report's window is not 9"
fi

# One input and -o ending in '/': written into that folder under its name.
expect 0 "1 of 1 inputs done" -- "$relief" complete-points "$tmp/in/cap1.ply" -o "$tmp/b/" --iterations 1 --max-hole 1000
ok '[[ -f $tmp/b/cap1.ply ]]' "complete-points: one input with -o DIR/ wrote no DIR/cap1.ply"

# Refused before any run, nothing written.
rm -rf "$tmp/b" && mkdir "$tmp/b"
expect 1 "is a folder that exists" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" -o "$tmp/missing/"
expect 1 "is a folder that exists" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" -o "$tmp/in/cap1.ply"
expect 1 "--report names one file" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" -o "$tmp/b/" --report "$tmp/b/r.json"
mkdir -p "$tmp/in2" && cp "$tmp/in/cap1.ply" "$tmp/in2/"
expect 1 "would both be written to" -- "$relief" depth-fill "$tmp/in/cap1.ply" "$tmp/in2/cap1.ply" -o "$tmp/b/"
ok '[[ -z $(ls -A "$tmp/b") ]]' "a refused batch wrote: $(ls "$tmp/b")"
expect 1 "unexpected argument" -- "$relief" fit "$tmp/in/cap1.ply" "$tmp/in/cap2.ply"

# Issue 60: the command line is parsed once and its job run per input, so
# every spelling getopt takes works (before, `--out DIR/` made the batch
# call itself until the stack overflowed, and `--rep` slipped past the
# refusal, every run writing the one report).
for spelling in "--out=$tmp/ab/" "--outp $tmp/ab/" "-o$tmp/ab/"; do
  rm -rf "$tmp/ab" && mkdir "$tmp/ab"
  # shellcheck disable=SC2086 # the spelling is two words or one
  expect 0 "2 of 2 inputs done" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" $spelling --backend scalar
  ok 'cmp -s "$tmp/ab/cap1.ply" "$tmp/one/cap1.ply" && cmp -s "$tmp/ab/cap2.ply" "$tmp/one/cap2.ply"' "$spelling: the batch's outputs differ from runs on each input alone"
done
rm -rf "$tmp/b" && mkdir "$tmp/b"
expect 1 "--report names one file" -- "$relief" image-fill "$tmp/x.png" "$tmp/y.png" --out "$tmp/b/" --rep "$tmp/b/r.json"
expect 1 "--report-dir names one file" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" -o "$tmp/b/" --report-d="$tmp/b/rd"
expect 1 "--resume names one file" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" -o "$tmp/b/" --resu "$tmp/b/ck"
expect 1 "--checkpoint names one file" -- "$relief" complete "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" --outp="$tmp/b/" --checkpoint="$tmp/b/ck"
expect 1 "--mesh names one file" -- "$relief" complete-points "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" -o "$tmp/b/" --mes "$tmp/b/m.ply"
expect 1 "--truth names one file" -- "$relief" depth-fill "$tmp/in/cap1.ply" "$tmp/in/cap2.ply" -o "$tmp/b/" --tr "$tmp/in/cap1.ply"
expect 1 "--points names one file" -- "$relief" depth-fill "$tmp/a.pcd" "$tmp/b.pcd" -o "$tmp/b/" --poi "$tmp/b/p.ply"
ok '[[ -z $(ls -A "$tmp/b") ]]' "a refused batch wrote: $(ls "$tmp/b")"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
