#!/usr/bin/env bash
# Outputs never destroy data (issue 40): every command checks every output
# before any work (a folder where a file is wanted, a missing folder, an
# input or another output named again: exit 1, one line naming the option
# and the path), writes every file beside its target and moves them all
# into place only once all are written; on any failure every file that was
# there keeps its bytes, mtime and inode, no folder is removed and no
# temporary is left.
# Usage: test_outputs.sh PATH/TO/relief PATH/TO/image_tool
set -u
relief=$1 itool=$2
tmp=$(mktemp -d /tmp/relief-outputs-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0

. "$(dirname "$0")/expect.sh" # expect, ok

in=$tmp/in w=$tmp/w
mkdir "$in" "$w"
"$relief" synth plane-waves -o "$in/pw.ply" --vertices 500 --colour 2>/dev/null
"$relief" synth sphere-dimples -o "$in/sd.ply" --vertices 800 2>/dev/null
"$relief" render "$in/pw.ply" -o "$in/img.png" --size 64x48 2>/dev/null
"$itool" mask "$in/m.png" 64 48 30 20 6 5
# A 16 x 12 organised PCD with a 3 x 2 hole.
{ printf 'VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 16\nHEIGHT 12\n'
  printf 'VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 192\nDATA ascii\n'
  for ((y = 0; y < 12; y++)); do for ((x = 0; x < 16; x++)); do
    if ((x >= 6 && x < 9 && y >= 5 && y < 7)); then echo "nan nan nan"; continue; fi
    z=$((100 + (x * x + y) % 7)); echo "$(((x - 8) * z))e-3 $(((y - 6) * z))e-3 ${z}e-2"
  done; done; } > "$in/f.pcd"

# What the user had: files with old mtimes, an empty folder for each kind of
# output, a second name (hard link) of an input.
for f in out.ply out.png out.pcd mesh.ply pts.ply truth.ply rep.json; do
  echo "the user's $f" > "$w/$f"; touch -d '2001-02-03 04:05:06' "$w/$f"
done
mkdir "$w/dir.ply" "$w/dir.png" "$w/dir.pcd" "$w/dir.json" "$w/ck"
ln "$in/pw.ply" "$w/alias.ply"
# Every entry of $w: its type, mtime (ns), inode, size and bytes.
snap() { (cd "$w" && find . -mindepth 1 ! -type d -printf '%p %y %T@ %i %s\n' | sort &&
           find . -mindepth 1 -type d -printf '%p %y %i\n' | sort &&
           find . -type f -exec md5sum {} + | sort); }
stamp() { stat -c '%Y.%y' "$w"; } # the folder's own mtime: changes when a temporary comes and goes

# refused NEEDLE -- COMMAND...: exit 1 with NEEDLE in one line, before any
# work: $w exactly as it was and no file ever created in it.
refused() {
  local needle=$1 before="$(snap)" dir="$(stamp)"; shift 2
  expect 1 "$needle" -- "$@"
  ok '[[ $(wc -l < "$tmp/err") -eq 1 ]]' "more than one line: $(cat "$tmp/err")"
  ok '[[ $(snap) == "$before" && $(stamp) == "$dir" ]]' "the user's files were touched by: ${*:2}"
}
# relief's temporaries anywhere under $tmp (base/output.h's one form; the
# marker inside a report folder is not one).
temps() { find "$tmp" -name '.relief-*' ! -name .relief-report | wc -l; }
# every_step HOOK CODE -- COMMAND...: writing fails (HOOK
# RELIEF_TEST_OUTPUT_FAIL: exit CODE 2) or the process is killed (HOOK
# RELIEF_TEST_OUTPUT_KILL: SIGKILL, CODE 137) at step 1, 2, ... of
# staging and commit, until a run gets past every step (then it must have
# succeeded). After each cut-short run, and after the next run's tidying
# (a `relief synth` writing into the same folder: it rolls back a dead
# commit's journal and removes dead temporaries), every file of the user's
# is as it was: bytes, mtime and inode. Returns the number of steps.
every_step() {
  local hook=$1 code=$2 s got before; shift 3
  for ((s = 1; s < 40; s++)); do
    before="$(snap)"
    env "$hook=$s" "$@" >/dev/null 2>"$tmp/err"
    got=$?
    [[ $got -eq 0 ]] && break # past every step: a whole run
    ok '[[ $got -eq $code ]]' "$hook=$s: exit $got, expected $code: ${*}"
    [[ $hook == RELIEF_TEST_OUTPUT_FAIL ]] &&
      ok 'grep -q "step $s (.*) failed" "$tmp/err" && [[ $(wc -l < "$tmp/err") -eq 1 ]]' \
         "$hook=$s: not one line naming the step: $(cat "$tmp/err")"
    ok '[[ $(find "$tmp" -name ".relief-*.relief-*" | wc -l) -eq 0 ]]' "$hook=$s: nested temporaries"
    for d in "$w" "$w"/*/; do # a later run writing into each folder tidies it
      "$relief" synth plane-waves -o "$d/.tidy.ply" --vertices 100 2>/dev/null
      rm -f "$d/.tidy.ply"
    done
    if grep -q "(cleanup)" "$tmp/err"; then # killed after the commit's point
      ok '[[ $(snap) != "$before" ]]' "$hook=$s: killed after the commit, the outputs are not new"
    else
      ok '[[ $(snap) == "$before" ]]' "$hook=$s changed the user's files: ${*}"
    fi
    ok '[[ $(temps) -eq 0 ]]' "$hook=$s: temporaries left after the next run: $(find "$tmp" -name '.relief-*')"
  done
  ok '[[ $s -gt 2 && $s -lt 40 ]]' "$hook: $s steps for: ${*}"
}
failed_each() { every_step RELIEF_TEST_OUTPUT_FAIL 2 -- "$@"; }
killed_each() { every_step RELIEF_TEST_OUTPUT_KILL 137 -- "$@" 2>/dev/null; }

# --------------------------------------------------------- before any work
# Each second output a folder, the one the issue found: refused at once, OUT
# and the folder kept (complete-points and complete removed both).
refused "--report: '$w/dir.json' is a folder" -- "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/out.png" --report "$w/dir.json"
refused "--report: '$w/dir.json' is a folder" -- "$relief" depth-fill "$in/f.pcd" -o "$w/out.pcd" --report "$w/dir.json"
refused "--points: '$w/dir.ply' is a folder" -- "$relief" depth-fill "$in/f.pcd" -o "$w/out.pcd" --points "$w/dir.ply"
refused "--mesh: '$w/dir.ply' is a folder" -- "$relief" complete-points "$in/pw.ply" -o "$w/out.ply" --mesh "$w/dir.ply"
refused "--report: '$w/dir.json' is a folder" -- "$relief" complete-points "$in/pw.ply" -o "$w/out.ply" --report "$w/dir.json"
refused "--report: '$w/dir.json' is a folder" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/dir.json"
refused "--report: '$w/dir.json' is a folder" -- "$relief" smooth "$in/pw.ply" -o "$w/out.ply" --report "$w/dir.json"
refused "--checkpoint: '$w/ck' is a folder" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --checkpoint "$w/ck"
refused "--truth: '$w/dir.ply' is a folder" -- "$relief" cut "$in/pw.ply" -o "$w/out.ply" --truth "$w/dir.ply" --ball 0,0,0,0.3
refused "--truth: '$w/dir.ply' is a folder" -- "$relief" synth plane-waves -o "$w/out.ply" --truth "$w/dir.ply"
# OUT a folder.
refused "-o: '$w/dir.png' is a folder" -- "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/dir.png"
refused "-o: '$w/dir.pcd' is a folder" -- "$relief" depth-fill "$in/f.pcd" -o "$w/dir.pcd"
refused "-o: '$w/dir.ply' is a folder" -- "$relief" depth-fill "$in/sd.ply" -o "$w/dir.ply"
refused "-o: '$w/dir.ply' is a folder" -- "$relief" complete-points "$in/pw.ply" -o "$w/dir.ply"
refused "-o: '$w/dir.ply' is a folder" -- "$relief" complete "$in/pw.ply" -o "$w/dir.ply"
refused "-o: '$w/dir.ply' is a folder" -- "$relief" smooth "$in/pw.ply" -o "$w/dir.ply"
refused "-o: '$w/dir.ply' is a folder" -- "$relief" cut "$in/pw.ply" -o "$w/dir.ply" --ball 0,0,0,0.3
refused "-o: '$w/dir.ply' is a folder" -- "$relief" synth plane-waves -o "$w/dir.ply"
refused "-o: '$w/dir.png' is a folder" -- "$relief" render "$in/pw.ply" -o "$w/dir.png"
refused "-o: '$w/x/' is a folder's name" -- "$relief" synth plane-waves -o "$w/x/"
# Not a plain file (a pipe here: renaming over /dev/null as root, as the
# command did, replaces the device).
mkfifo "$w/pipe.json"
refused "--report: '$w/pipe.json' is there and is not a plain file" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/pipe.json"
# A folder that is not there.
no=$w/no/such
refused "-o: '$no.png' cannot be written: the folder '$w/no' does not exist" -- "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$no.png"
refused "--report: '$no.json' cannot be written" -- "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/out.png" --report "$no.json"
refused "--points: '$no.ply' cannot be written" -- "$relief" depth-fill "$in/f.pcd" -o "$w/out.pcd" --points "$no.ply"
refused "--report: '$no.json' cannot be written" -- "$relief" depth-fill "$in/sd.ply" -o "$w/out.ply" --report "$no.json"
refused "--mesh: '$no.ply' cannot be written" -- "$relief" complete-points "$in/pw.ply" -o "$w/out.ply" --mesh "$no.ply"
refused "--report: '$no.json' cannot be written" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$no.json"
refused "--checkpoint: '$no' cannot be written" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --checkpoint "$no"
refused "--report-dir: $no: the folder it goes in, '$w/no', does not exist" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report-dir "$no"
refused "-o: '$no.ply' cannot be written" -- "$relief" smooth "$in/pw.ply" -o "$no.ply"
refused "--truth: '$no.ply' cannot be written" -- "$relief" cut "$in/pw.ply" -o "$w/out.ply" --truth "$no.ply" --ball 0,0,0,0.3
refused "--truth: '$no.ply' cannot be written" -- "$relief" synth plane-waves -o "$w/out.ply" --truth "$no.ply"
refused "-o: '$no.png' cannot be written" -- "$relief" render "$in/pw.ply" -o "$no.png"
# An input under a second name (the same inode), and one file named twice.
refused "-o: '$w/alias.ply' is an input" -- "$relief" complete "$in/pw.ply" -o "$w/alias.ply"
refused "--mesh: '$w/alias.ply' is an input" -- "$relief" complete-points "$in/pw.ply" -o "$w/out.ply" --mesh "$w/alias.ply"
refused "--truth: '$w/alias.ply' is an input" -- "$relief" cut "$in/pw.ply" -o "$w/out.ply" --truth "$w/alias.ply" --ball 0,0,0,0.3
refused "-o: '$w/alias.ply' is an input" -- "$relief" depth-fill "$in/pw.ply" -o "$w/alias.ply"
refused "--report: '$w/../w/out.png' is also named by -o" -- "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/out.png" --report "$w/../w/out.png"
refused "--report: '$w/./new.json' is also named by --points" -- "$relief" depth-fill "$in/f.pcd" -o "$w/out.pcd" --points "$w/new.json" --report "$w/./new.json"
refused "--truth: '$w/../w/out.ply' is also named by -o" -- "$relief" synth plane-waves -o "$w/out.ply" --truth "$w/../w/out.ply"
refused "--report-dir: '$w/rep.json' is also named by --report" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/rep.json" --report-dir "$w/rep.json"
# Before the input is read: an input that is not there is not what is said.
refused "--report: '$w/dir.json' is a folder" -- "$relief" complete "$in/none.ply" -o "$w/out.ply" --report "$w/dir.json"
refused "--mesh: '$w/dir.ply' is a folder" -- "$relief" complete-points "$in/none.ply" -o "$w/out.ply" --mesh "$w/dir.ply"
refused "--report: '$w/dir.json' is a folder" -- "$relief" image-fill "$in/none.png" -o "$w/out.png" --report "$w/dir.json"
refused "--report: '$w/dir.json' is a folder" -- "$relief" depth-fill "$in/none.pcd" -o "$w/out.pcd" --report "$w/dir.json"

# ---------------------------------------------- --max-seconds
# A run past its time limit stops at its next step of progress: exit 1, the
# limit named, nothing written (1e-9 s: any run is past it at once).
lim="over --max-seconds 1e-09"
refused "$lim" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/rep.json" --max-seconds 1e-9 --quiet
refused "$lim" -- "$relief" complete-points "$in/pw.ply" -o "$w/out.ply" --max-hole 10 --max-seconds 1e-9 --quiet
refused "$lim" -- "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/out.png" --max-seconds 1e-9 --quiet
refused "$lim" -- "$relief" depth-fill "$in/f.pcd" -o "$w/out.pcd" --max-seconds 1e-9 --quiet
refused "$lim" -- "$relief" depth-fill "$in/sd.ply" -o "$w/out.ply" --resolution 24 --solid --max-seconds 1e-9 --quiet
refused "--max-seconds: '-1' is not a number of seconds >= 0" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --max-seconds -1
refused "--max-seconds: 'soon' is not a number" -- "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/out.png" --max-seconds soon

# ---------------------------------------------- a failure while writing
# Each step of the writing fails in turn (every file written beside its
# target, the journal, each previous file kept and each new one moved into
# place, the commit): exit 2 (a resource failure) with one line naming the
# step, the user's files keep their bytes, mtime and inode, and no
# temporary is left. (complete grows with the coherent search: what is
# tested is the writing.)
failed_each "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/rep.json" --backend scalar --search coherent --quiet
failed_each "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/rep.json" --report-dir "$w/repdir" --backend scalar --search coherent --quiet
rm -rf "$w/repdir"
# (--max-hole 10: the plane's hole is wider than the default quarter of its box.)
failed_each "$relief" complete-points "$in/pw.ply" -o "$w/out.ply" --mesh "$w/mesh.ply" --report "$w/rep.json" --max-hole 10 --quiet
failed_each "$relief" depth-fill "$in/f.pcd" -o "$w/out.pcd" --points "$w/pts.ply" --report "$w/rep.json" --backend scalar --quiet
failed_each "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/out.png" --report "$w/rep.json" --quiet
failed_each "$relief" depth-fill "$in/sd.ply" -o "$w/out.ply" --report "$w/rep.json" --resolution 24 --solid --quiet
failed_each "$relief" smooth "$in/pw.ply" -o "$w/out.ply" --report "$w/rep.json" --quiet
failed_each "$relief" cut "$in/pw.ply" -o "$w/out.ply" --truth "$w/truth.ply" --ball 0,0,0,0.3
failed_each "$relief" synth plane-waves -o "$w/out.ply" --truth "$w/truth.ply"
failed_each "$relief" render "$in/pw.ply" -o "$w/out.png"
# A new output is removed with the rest (it was not there before).
failed_each "$relief" synth plane-waves -o "$w/new.ply" --truth "$w/new-truth.ply"
rm -f "$w/new.ply" "$w/new-truth.ply"

# ------------------------------------------------- a kill while writing
# A power cut (SIGKILL) at each step: the outputs are all as they were or,
# once the next run over their folder has rolled the journal back or
# forward, all new; never a mix, never a temporary left. Two outputs in
# two folders, each replacing a file, and a report folder.
mkdir -p "$w/sub"
echo "the user's sub.json" > "$w/sub/rep.json"; touch -d '2001-02-03 04:05:06' "$w/sub/rep.json"
killed_each "$relief" depth-fill "$in/f.pcd" -o "$w/out.pcd" --points "$w/pts.ply" --report "$w/sub/rep.json" --backend scalar --quiet
killed_each "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/sub/rep.json" --report-dir "$w/repdir" --backend scalar --search coherent --quiet
killed_each "$relief" image-fill "$in/img.png" --mask "$in/m.png" -o "$w/out.png" --quiet
rm -rf "$w/sub" "$w/repdir"

# ------------------------------------------------ a signal at any moment
# SIGTERM, SIGHUP or SIGQUIT at any moment of a run that writes a mesh, a
# report and a report folder (reading, growing, rendering the folder,
# writing): the run either finishes (exit 0, every output new) or dies of
# the signal (128 + its number) with every file as it was and no
# temporary, staged folder or journal left. (The moments are spread by
# sleeping; whichever one a signal lands in, the same must hold.)
for sig in TERM HUP QUIT; do
  for delay in 0.05 0.2 0.4 0.7 1.0 1.5; do
    rm -rf "$w/sigdir"
    before="$(snap)"
    "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/rep.json" --report-dir "$w/sigdir" \
      --backend scalar --quiet 2>"$tmp/err" &
    pid=$!
    sleep "$delay"
    kill -"$sig" "$pid" 2>/dev/null
    wait "$pid"
    got=$?
    [[ $got -eq 0 ]] || ok '[[ $got -eq $((128 + $(kill -l "$sig"))) ]]' "SIG$sig after $delay s: exit $got: $(cat "$tmp/err")"
    if [[ -f $w/sigdir/index.html ]]; then # finished, or held until its commit was done
      ok '[[ $(snap) != "$before" ]]' "SIG$sig after $delay s: a report folder, the other outputs not new"
    else
      ok '[[ $got -ne 0 && ! -e $w/sigdir && $(snap) == "$before" ]]' "SIG$sig after $delay s (exit $got) changed the user's files"
    fi
    ok '[[ $(temps) -eq 0 ]]' "SIG$sig after $delay s left temporaries: $(find "$tmp" -name '.relief-*')"
  done
done
rm -rf "$w/sigdir"

# -------------------------------------------- and when all goes well
# The outputs replace the files there.
expect 0 "" -- "$relief" complete "$in/pw.ply" -o "$w/out.ply" --report "$w/rep.json" --backend scalar --search coherent --quiet
ok 'grep -q "^ply" "$w/out.ply" && grep -q "\"spacing\"" "$w/rep.json"' "the outputs did not replace the files there"
expect 0 "" -- "$relief" complete-points "$in/pw.ply" -o "$w/out.ply" --mesh "$w/mesh.ply" --report "$w/rep.json" --max-hole 10 --quiet
ok 'grep -q "^ply" "$w/mesh.ply" && grep -q "\"holes\"" "$w/rep.json"' "complete-points did not replace the files there"
ok '[[ -d $w/dir.ply && -d $w/dir.json && -d $w/ck ]]' "a folder named as an output was removed"
ok '[[ $(temps) -eq 0 ]]' "temporary files left"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
