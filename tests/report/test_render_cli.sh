#!/usr/bin/env bash
# relief render and relief complete --report-dir: images of the right size
# that decode and are not blank (checked by test_render's PNG decoder), an
# index.html that references only files that exist, clear errors (exit 1)
# and no partial output. Usage: test_render_cli.sh PATH/TO/relief PATH/TO/test_render
set -u
relief=$1
checker=$2
tmp=$(mktemp -d /tmp/relief-render-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

ok() { pass=$((pass+1)); }
bad() { echo "FAIL: $*"; fail=$((fail+1)); }

# expect CODE [NEEDLE] -- COMMAND...: exit code CODE and, if given, NEEDLE in stderr.
expect() {
  local want=$1 needle=$2; shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  if [[ $got -ne $want ]]; then
    bad "exit $got, expected $want: $*"; sed 's/^/  /' "$tmp/err"; return
  fi
  if [[ -n $needle ]] && ! grep -qF -- "$needle" "$tmp/err" "$tmp/out"; then
    bad "no '$needle' in the output of: $*"; sed 's/^/  /' "$tmp/err"; return
  fi
  ok
}

# png FILE W H [MIN_COLOURS]: decodes, W x H, not blank.
png() {
  if "$checker" png "$@" >"$tmp/png.out" 2>&1; then ok; else bad "$(cat "$tmp/png.out")"; fi
}

"$relief" synth plane-waves --colour --vertices 600 --seed 3 -o "$tmp/cap.ply" --truth "$tmp/truth.ply" 2>/dev/null
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n' > "$tmp/square.off"

# relief render: sizes, views, every colouring.
expect 0 "usage: relief render" -- "$relief" render --help
expect 0 "(800x600," -- "$relief" render "$tmp/cap.ply" -o "$tmp/default.png"
png "$tmp/default.png" 800 600
expect 0 "view 30.0,45.0, colour by label" -- "$relief" render "$tmp/truth.ply" -o "$tmp/label.png" \
  --size 320x200 --view 30,45 --colour-by label
png "$tmp/label.png" 320 200
# both classes show: the completed disc in orange, the rest grey
if grep -Eq ' [1-9][0-9]* orange, [1-9][0-9]* grey' "$tmp/png.out"; then ok; else bad "label render lacks a class: $(cat "$tmp/png.out")"; fi
expect 0 "colour by displacement" -- "$relief" render "$tmp/truth.ply" -o "$tmp/disp.png" \
  --size 200x300 --colour-by displacement --view -120,-30
png "$tmp/disp.png" 200 300
expect 0 "colour by none" -- "$relief" render "$tmp/square.off" -o "$tmp/sq.png" --colour-by none --size 64x64
png "$tmp/sq.png" 64 64 3 # one flat square: its shade, and edge blends

# Bad input: exit 1, a message that names the problem, no image left.
expect 1 "missing input MESH" -- "$relief" render -o "$tmp/x.png"
expect 1 "missing -o" -- "$relief" render "$tmp/cap.ply"
expect 1 "does not end in .png" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.jpg"
expect 1 "cannot open" -- "$relief" render "$tmp/nope.ply" -o "$tmp/x.png"
expect 1 "'800' is not WIDTHxHEIGHT" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --size 800
expect 1 "'axb' is not WIDTHxHEIGHT" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --size axb
expect 1 "0x600 is out of range" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --size 0x600
expect 1 "out of range" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --size 9000x10
expect 1 "'30' is not AZIMUTH,ELEVATION" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --view 30
expect 1 "'a,b' is not AZIMUTH,ELEVATION" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --view a,b
expect 1 "elevation 100 is out of range" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --view 0,100
expect 1 "'rainbow' is not one of" -- "$relief" render "$tmp/cap.ply" -o "$tmp/x.png" --colour-by rainbow
expect 1 "square.off: the mesh has no per-vertex colour" -- "$relief" render "$tmp/square.off" -o "$tmp/x.png" --colour-by colour
expect 1 "square.off: the mesh has no label property" -- "$relief" render "$tmp/square.off" -o "$tmp/x.png" --colour-by label
expect 1 "cannot" -- "$relief" render "$tmp/cap.ply" -o "$tmp/nodir/x.png"
[[ ! -e $tmp/x.png && ! -e $tmp/x.jpg ]] && ok || bad "an image was left after a failed render"

# complete --report-dir: every file index.html names exists, the renders
# decode at the report's size and are not blank, report.json is --report's.
rep=$tmp/rep
expect 0 "report folder: $rep/index.html" -- "$relief" complete "$tmp/cap.ply" -o "$tmp/done.ply" \
  --report "$tmp/r.json" --report-dir "$rep" --backend scalar
[[ -f $rep/index.html ]] && ok || bad "no index.html"
refs=$(grep -oE '(src|href)="[^"]+"' "$rep/index.html" | sed -E 's/^(src|href)="//; s/"$//' | sort -u)
nrefs=0
for r in $refs; do
  nrefs=$((nrefs+1))
  case $r in */*|*..*) bad "index.html refers outside its folder: $r"; continue ;; esac
  [[ -f $rep/$r ]] && ok || bad "index.html refers to $r, which does not exist"
done
[[ $nrefs -ge 20 ]] && ok || bad "index.html refers to only $nrefs files"
npng=0
for f in "$rep"/*.png; do npng=$((npng+1)); png "$f" 640 480; done
[[ $npng -eq 15 ]] && ok || bad "$npng renders, expected 15 (5 stages x 3 views)"
for h in displacement red green blue; do
  grep -q '<svg' "$rep/hist-$h.svg" 2>/dev/null && ok || bad "no histogram hist-$h.svg"
done
# --report is the folder's report.json with what the command line read
# first: the input's repair on reading (one line, "input_repair").
grep -v '^  "input_repair": ' "$tmp/r.json" | cmp -s - "$rep/report.json" && ok ||
  bad "report.json differs from --report's (but for input_repair)"
grep -q 'msi_diff_percent' "$rep/report.json" && grep -q 'MSI difference' "$rep/index.html" && ok \
  || bad "the measures are missing from the report"

# Again over the previous report: replaced, nothing left beside it.
expect 0 "" -- "$relief" complete "$tmp/cap.ply" -o "$tmp/done.ply" --report-dir "$rep" --backend scalar --quiet
[[ -f $rep/index.html ]] && ok || bad "the report was not replaced"
[[ -f $rep/.relief-report ]] && ok || bad "the report folder carries no marker"
# A folder relief did not write is not replaced, and that fails before the
# work: one holding something else, and one of the user's pictures that
# looks like a report (only *.png and index.html, no marker; issue 60).
mkdir -p "$tmp/mine" && echo keep > "$tmp/mine/notes.txt"
expect 1 "relief did not write (no .relief-report marker)" -- "$relief" complete "$tmp/cap.ply" -o "$tmp/d2.ply" --report-dir "$tmp/mine"
[[ -f $tmp/mine/notes.txt && ! -e $tmp/d2.ply ]] && ok || bad "a foreign folder was touched"
mkdir -p "$tmp/pics" && cp "$rep"/captured-view1.png "$tmp/pics/holiday.png" && echo '<html>' > "$tmp/pics/index.html"
expect 1 "relief did not write (no .relief-report marker)" -- "$relief" complete "$tmp/cap.ply" -o "$tmp/d2.ply" --report-dir "$tmp/pics"
[[ -f $tmp/pics/holiday.png && -f $tmp/pics/index.html && ! -e $tmp/d2.ply ]] && ok || bad "a folder of pictures was touched"
# A report of relief's to which the user added a file of their own.
cp -r "$rep" "$tmp/mine2" && echo keep > "$tmp/mine2/notes.txt"
expect 1 "holds 'notes.txt'" -- "$relief" complete "$tmp/cap.ply" -o "$tmp/d2.ply" --report-dir "$tmp/mine2"
[[ -f $tmp/mine2/notes.txt && ! -e $tmp/d2.ply ]] && ok || bad "a report with the user's notes was touched"
expect 1 "does not exist" -- "$relief" complete "$tmp/cap.ply" -o "$tmp/d2.ply" --report-dir "$tmp/no/such"
# A failure after the report is staged (the mesh cannot be moved into
# place: the test hook) leaves no report.
expect 2 "step 2 (journal) failed" -- env RELIEF_TEST_OUTPUT_FAIL=2 "$relief" complete "$tmp/cap.ply" -o "$tmp/d.ply" --report-dir "$tmp/rep2" --backend scalar --quiet
[[ ! -e $tmp/d.ply ]] && ok || bad "a mesh was left after a failed run"
[[ ! -e $tmp/rep2 ]] && ok || bad "a report folder was left after a failed run"
leftovers=$(find "$tmp" -name '.relief-*' ! -name .relief-report | wc -l)
[[ $leftovers -eq 0 ]] && ok || bad "$leftovers temporary files or folders left"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
