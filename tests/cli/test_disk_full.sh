#!/usr/bin/env bash
# A full disk under every writer (issue 60 item 1): every output kind of
# every command is written onto a file system with no room for it, over an
# older file of the user's. Each run must exit 2 with exactly one line on
# stderr naming the user's path (never a .relief-* temporary) and the
# system's reason; the older file keeps its bytes, size, mtime and inode,
# no temporary is left, and a command's other outputs (in a roomy folder)
# are not changed either.
#
# The full disk is a small tmpfs this script mounts when it runs as root (as
# CI does), filled but for FREE bytes; otherwise, or when the mount fails, a
# file size limit (ulimit -f, SIGXFSZ ignored so that write() returns EFBIG)
# stands in for it, which every file of the run shares.
#   test_disk_full.sh RELIEF IMAGE_TOOL DEPTH_TOOL TEST_API_OCCLUDERS [DATA_DIR]
# (the test tools make the inputs: build/tests/{image_tool,depth_tool,
# test_api_occluders}). Exit 77 when neither way works.
# DISK_FULL=rlimit takes the file size limit even as root; VERBOSE=1 prints
# each run's exit status and line.
set -u
relief=$1 itool=$2 dtool=$3 otool=$4
data=${5:-$(cd "$(dirname "$0")/../../.." && pwd)/shared/data}
tmp=$(mktemp -d /tmp/relief-diskfull-XXXXXX)
full=$tmp/full room=$tmp/room in=$tmp/in
mkdir "$full" "$room" "$in"
mounted=0
cleanup() {
  ((mounted)) && umount "$full" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
pass=0 fail=0 cases=0 bad=0 fail_then=0
. "$(dirname "$0")/expect.sh" # ok

# ------------------------------------------------------- the full disk
if [[ ${DISK_FULL:-} != rlimit && $(id -u) -eq 0 ]] &&
   mount -t tmpfs -o size=1m,mode=0755 tmpfs "$full" 2>/dev/null; then
  mounted=1 mode=tmpfs reason="No space left on device"
else
  # The limit must hold, and write() must fail with EFBIG (no signal).
  (ulimit -f 1 && trap '' XFSZ && exec head -c 4096 /dev/zero > "$tmp/probe") 2>/dev/null
  if [[ $? -eq 0 || $(stat -c %s "$tmp/probe" 2>/dev/null) != 1024 ]]; then
    echo "test_disk_full: SKIP: neither a tmpfs (needs root) nor a file size limit (ulimit -f)"
    exit 77
  fi
  mode=rlimit reason="File too large"
fi
rm -f "$tmp/probe"
echo "test_disk_full: the full disk is a $mode ($reason)"

# --------------------------------------------------------------- inputs
# Small, so that each run takes a tenth of a second.
"$relief" synth plane-waves -o "$in/pw.ply" --vertices 500 --colour 2>/dev/null
"$relief" synth sphere-dimples -o "$in/sd.ply" --vertices 800 2>/dev/null
"$relief" render "$in/pw.ply" -o "$in/img.png" --size 64x48 2>/dev/null
"$itool" mask "$in/m.png" 64 48 30 20 6 5
"$itool" deep "$in/img.png" "$in/img16.png"
for k in pcd-ascii pcd-binary pcd-compressed; do
  "$dtool" crop "$data/depth/office1.pcd" 200 150 40 30 "$in/$k.pcd" "$k"
done
"$dtool" crop "$data/depth/motorcycle_disp.pfm" 300 200 40 30 "$in/moto.pfm"
"$dtool" png16 "$in/pcd-binary.pcd" 5000 "$in/depth16.png"
"$itool" mask "$in/dm.png" 40 30 10 10 6 5
"$otool" --write "$in" >/dev/null
"$dtool" crop "$in/scene.pcd" 80 60 160 120 "$in/sc.pcd"
"$relief" occluders "$in/sc.pcd" -o "$in/sc-mask.png" --quiet
"$relief" remove-occluders "$in/sc.pcd" -o "$in/sc-out.pcd" --colour-out "$in/sc-colour.png" --quiet
"$dtool" png16 "$in/sc.pcd" 5000 "$in/sc-depth.png"
# What the user had: an older report folder (its marker, so that relief may
# replace it, and two of its files) and an older checkpoint of the run below.
"$relief" complete "$in/pw.ply" -o "$in/c.ply" --report-dir "$in/rd" --backend scalar --quiet
mkdir "$in/old-rd"
cp "$in/rd/.relief-report" "$in/rd/report.json" "$in/rd/index.html" "$in/old-rd/"
env RELIEF_TEST_SIGINT_AFTER=5 "$relief" complete "$in/pw.ply" -o "$in/c.ply" \
  --checkpoint "$in/old.ckpt" --backend scalar --quiet 2>/dev/null
for f in "$in/pw.ply" "$in/sc-mask.png" "$in/sc-colour.png" "$in/old.ckpt" "$in/old-rd/index.html"; do
  [[ -s $f ]] || { echo "FAIL: cannot make the input $f"; exit 1; }
done

# ---------------------------------------------------------------- a case
# Every entry under the two folders: type, mtime (ns), inode, size, bytes.
snap() {
  (cd "$tmp" && find full room -mindepth 1 -printf '%p %y %T@ %i %s\n' | sort &&
   find full room -type f -exec md5sum {} + | sort)
}
# relief's temporaries (base/output.h's one form; a report folder's marker
# is not one).
temps() { find "$full" "$room" -name '.relief-*' ! -name .relief-report; }
# What the user had at OUT: an older report folder (OUT/), an older
# checkpoint (*.ckpt) or a file of its own, all with an old mtime.
older() {
  local out=${1%/}
  if [[ $1 == */ ]]; then cp -a "$in/old-rd" "$out"
  elif [[ $out == *.ckpt ]]; then cp "$in/old.ckpt" "$out"
  else echo "the user's older ${out##*/}" > "$out"
  fi
  touch -h -d '2001-02-03 04:05:06' "$out"
}
# Fill $full but for FREE bytes (tmpfs; under the limit, nothing to do).
fill() {
  if [[ $mode == tmpfs ]]; then
    local avail=$(($(stat -f -c '%a * %S' "$full")))
    ((avail > $1)) && head -c $((avail - $1)) /dev/zero > "$full/filler" 2>/dev/null
  fi
}
# Run the command, its stderr into $tmp/err (through a pipe under the
# limit, which would cut a file short too); its exit status.
run_full() {
  if [[ $mode == tmpfs ]]; then
    "$@" >/dev/null 2>"$tmp/err"
    return
  fi
  (ulimit -f "$limit" && trap '' XFSZ && exec "$@" 2>&1 >/dev/null) | cat > "$tmp/err"
  return "${PIPESTATUS[0]}"
}

# [code=N] full FREE OUT... -- COMMAND...: the OUTs (a trailing / for a
# report folder) are there beforehand as the user's older files; those in
# $full have no room (tmpfs: FREE bytes free; rlimit: a limit of FREE bytes
# on every file). The command must exit 2 (or N) with one line naming an
# OUT in $full (rlimit: any OUT) and the reason, and leave every file as it
# was.
full() {
  local free=$1 outs=() named=() before after got o line free_before
  shift
  while [[ $1 != -- ]]; do outs+=("$1"); shift; done
  shift
  cases=$((cases + 1))
  ((fail > fail_then)) && bad=$((bad + 1)) # the case before failed
  fail_then=$fail
  rm -rf "$full"/* "$full"/.[!.]* "$room"/* "$room"/.[!.]*
  for o in "${outs[@]}"; do
    older "$o"
    [[ $mode == rlimit || $o == "$full"/* ]] && named+=("${o%/}")
  done
  limit=$((free / 1024))
  fill "$free"
  before=$(snap)
  free_before=$(stat -f -c %a "$full")
  run_full "$@"
  got=$?
  line=$(head -n 1 "$tmp/err")
  [[ -n ${VERBOSE:-} ]] && echo "exit $got: $line"
  after=$(snap)
  local what="${*:2}"
  what=${what//$tmp\//}
  ok '[[ $got -eq ${code:-2} ]]' "exit $got, expected ${code:-2}: $what: $(cat "$tmp/err")"
  ok '[[ $(wc -l < "$tmp/err") -eq 1 ]]' "not one line on stderr: $what: $(cat "$tmp/err")"
  local hit=0
  for o in "${named[@]}"; do [[ $line == *"$o"* ]] && hit=1; done
  ok '((hit)) && [[ $line == *"$reason"* ]]' "no path of an output in $mode and '$reason': $what: $line"
  ok '! [[ $line =~ \.relief-(tmp|old|log)- ]]' "a temporary named: $what: $line"
  ok '[[ $after == "$before" ]]' "the user's files changed: $what: $(diff <(echo "$before") <(echo "$after") | grep '^[<>]' | head -4 | tr '\n' ' ')"
  ok '[[ -z $(temps) ]]' "temporaries left: $what: $(temps | tr '\n' ' ')"
  [[ $mode == tmpfs ]] &&
    ok '[[ $(stat -f -c %a "$full") == "$free_before" ]]' "the full file system's free blocks changed: $what"
}

F=$full R=$room
# synth and cut: each mesh format, as -o and as --truth.
for fmt in ply ascii.ply obj off stl; do
  a=(); [[ $fmt == ascii.ply ]] && a=(--ascii)
  full 8192 "$F/s.$fmt" -- "$relief" synth plane-waves -o "$F/s.$fmt" --vertices 2000 "${a[@]}"
  full 8192 "$R/s.ply" "$F/t.$fmt" -- "$relief" synth plane-waves -o "$R/s.ply" --truth "$F/t.$fmt" --vertices 2000 "${a[@]}"
  full 8192 "$F/c.$fmt" -- "$relief" cut "$in/pw.ply" -o "$F/c.$fmt" --ball 0,0,0,0.3 "${a[@]}"
  full 8192 "$R/c.ply" "$F/t.$fmt" -- "$relief" cut "$in/pw.ply" -o "$R/c.ply" --truth "$F/t.$fmt" --ball 0,0,0,0.3 "${a[@]}"
done
# complete: -o (two formats), --report, --report-dir; a checkpoint.
cmp=("$relief" complete "$in/pw.ply" --backend scalar --search coherent --quiet)
full 8192 "$F/c.ply" "$R/r.json" -- "${cmp[@]}" -o "$F/c.ply" --report "$R/r.json"
full 8192 "$F/c.obj" -- "${cmp[@]}" -o "$F/c.obj"
full 0 "$R/c.ply" "$F/r.json" -- "${cmp[@]}" -o "$R/c.ply" --report "$F/r.json"
full 0 "$R/c.ply" "$R/r.json" "$F/rd/" -- "${cmp[@]}" -o "$R/c.ply" --report "$R/r.json" --report-dir "$F/rd"
# (Room for the folder's marker and a little more: a render fails.)
full 16384 "$R/c.ply" "$F/rd/" -- "${cmp[@]}" -o "$R/c.ply" --report-dir "$F/rd"
# The checkpoint a cancel saves (SIGINT after 5 targets): one line saying
# it is not saved, with the reason, the older checkpoint kept, and the
# process ends of its SIGINT (130) as a cancelled one does.
code=130 full 0 "$R/c.ply" "$F/k.ckpt" -- env RELIEF_TEST_SIGINT_AFTER=5 "${cmp[@]}" -o "$R/c.ply" --checkpoint "$F/k.ckpt"
ok 'grep -q "checkpoint is not saved" "$tmp/err"' "a cancel's failed save does not say the checkpoint is not saved: $(cat "$tmp/err")"
# And the one a device failure saves: exit 2, never "state saved" on the
# strength of the older checkpoint. (Not under the file size limit: PoCL
# cannot cache its kernels there.)
if [[ $mode == tmpfs ]] && "$relief" devices 2>/dev/null | grep -q "^device 0"; then
  full 0 "$R/c.ply" "$F/k.ckpt" -- env RELIEF_TEST_DEVICE_FAIL_AFTER=5 "${cmp[@]/scalar/opencl}" -o "$R/c.ply" --checkpoint "$F/k.ckpt"
  ok 'grep -q "checkpoint is not saved" "$tmp/err"' "a device failure's failed save does not say the checkpoint is not saved: $(cat "$tmp/err")"
fi
# smooth.
full 8192 "$F/s.ply" "$R/r.json" -- "$relief" smooth "$in/pw.ply" -o "$F/s.ply" --report "$R/r.json" --quiet
full 8192 "$F/s.off" -- "$relief" smooth "$in/pw.ply" -o "$F/s.off" --ascii --quiet
full 0 "$R/s.ply" "$F/r.json" -- "$relief" smooth "$in/pw.ply" -o "$R/s.ply" --report "$F/r.json" --quiet
# complete-points: -o, --mesh, --report.
pts=("$relief" complete-points "$in/pw.ply" --max-hole 10 --iterations 2 --quiet)
full 8192 "$F/p.ply" "$R/m.ply" "$R/r.json" -- "${pts[@]}" -o "$F/p.ply" --mesh "$R/m.ply" --report "$R/r.json"
full 8192 "$R/p.ply" "$F/m.ply" "$R/r.json" -- "${pts[@]}" -o "$R/p.ply" --mesh "$F/m.ply" --report "$R/r.json"
full 0 "$R/p.ply" "$R/m.ply" "$F/r.json" -- "${pts[@]}" -o "$R/p.ply" --mesh "$R/m.ply" --report "$F/r.json"
# depth-fill: each frame format as -o, --points, --report; a mesh.
df=("$relief" depth-fill --mask "$in/dm.png" --backend scalar --quiet)
for k in pcd-ascii pcd-binary pcd-compressed; do
  full 0 "$F/d.pcd" "$R/p.ply" "$R/r.json" -- "${df[@]}" "$in/$k.pcd" -o "$F/d.pcd" --points "$R/p.ply" --report "$R/r.json"
done
full 0 "$F/d.pfm" -- "$relief" depth-fill "$in/moto.pfm" -o "$F/d.pfm" --quiet
full 0 "$F/d.png" -- "${df[@]}" "$in/depth16.png" -o "$F/d.png"
full 0 "$R/d.pcd" "$F/p.ply" "$R/r.json" -- "${df[@]}" "$in/pcd-binary.pcd" -o "$R/d.pcd" --points "$F/p.ply" --report "$R/r.json"
full 0 "$R/d.pcd" "$R/p.ply" "$F/r.json" -- "${df[@]}" "$in/pcd-binary.pcd" -o "$R/d.pcd" --points "$R/p.ply" --report "$F/r.json"
dm=("$relief" depth-fill "$in/sd.ply" --resolution 24 --solid --quiet)
full 8192 "$F/d.ply" "$R/r.json" -- "${dm[@]}" -o "$F/d.ply" --report "$R/r.json"
full 0 "$R/d.ply" "$F/r.json" -- "${dm[@]}" -o "$R/d.ply" --report "$F/r.json"
# image-fill: PNG of 8 and 16 bits, JPEG, --report.
im=(--mask "$in/m.png" --quiet)
full 0 "$F/i.png" "$R/r.json" -- "$relief" image-fill "$in/img.png" "${im[@]}" -o "$F/i.png" --report "$R/r.json"
full 0 "$F/i.png" -- "$relief" image-fill "$in/img16.png" "${im[@]}" -o "$F/i.png"
full 0 "$F/i.jpg" -- "$relief" image-fill "$in/img.png" "${im[@]}" -o "$F/i.jpg"
full 0 "$R/i.png" "$F/r.json" -- "$relief" image-fill "$in/img.png" "${im[@]}" -o "$R/i.png" --report "$F/r.json"
# Room for the report (1 KiB: one page) but not for the commit's journal
# beside it: the failure names the report, not -o in the roomy folder.
[[ $mode == tmpfs ]] &&
  full 4096 "$R/i.png" "$F/r.json" -- "$relief" image-fill "$in/img.png" "${im[@]}" -o "$R/i.png" --report "$F/r.json"
# occluders: -o, --report, --overlay.
oc=("$relief" occluders "$in/sc.pcd" --quiet)
full 0 "$F/o.png" "$R/r.json" "$R/v.png" -- "${oc[@]}" -o "$F/o.png" --report "$R/r.json" --overlay "$R/v.png"
full 0 "$R/o.png" "$F/r.json" "$R/v.png" -- "${oc[@]}" -o "$R/o.png" --report "$F/r.json" --overlay "$R/v.png"
full 0 "$R/o.png" "$R/r.json" "$F/v.png" -- "${oc[@]}" -o "$R/o.png" --report "$R/r.json" --overlay "$F/v.png"
# remove-occluders on a PCD: -o, --report, --overlay, --occluders,
# --colour-out, --points; on a colour and depth PNG: -o, --depth-out.
ro=("$relief" remove-occluders "$in/sc.pcd" --mask "$in/sc-mask.png" --backend scalar --quiet)
ro_outs=(-o o.pcd --report r.json --overlay v.png --occluders m.png --colour-out c.png --points p.ply)
for ((i = 0; i < ${#ro_outs[@]}; i += 2)); do
  args=() outs=()
  for ((j = 0; j < ${#ro_outs[@]}; j += 2)); do
    d=$R; ((i == j)) && d=$F
    args+=("${ro_outs[j]}" "$d/${ro_outs[j + 1]}"); outs+=("$d/${ro_outs[j + 1]}")
  done
  full 0 "${outs[@]}" -- "${ro[@]}" "${args[@]}"
done
rc=("$relief" remove-occluders "$in/sc-colour.png" --depth "$in/sc-depth.png" --mask "$in/sc-mask.png" --backend scalar --quiet)
full 0 "$F/o.png" "$R/d.png" -- "${rc[@]}" -o "$F/o.png" --depth-out "$R/d.png"
full 0 "$R/o.png" "$F/d.png" -- "${rc[@]}" -o "$R/o.png" --depth-out "$F/d.png"
# render.
full 0 "$F/r.png" -- "$relief" render "$in/pw.ply" -o "$F/r.png" --size 64x48

((fail > fail_then)) && bad=$((bad + 1))

# A read-only file system (root: a tmpfs mounted ro) is the system's to
# name, and a resource failure: exit 2 with "Read-only file system", never
# "no permission" (issue 60 item 10), before any work and the file kept.
if [[ $mode == tmpfs ]] && mkdir "$tmp/ro" && mount -t tmpfs -o size=64k tmpfs "$tmp/ro" 2>/dev/null; then
  echo "the user's" > "$tmp/ro/x.ply"
  mount -o remount,ro "$tmp/ro" 2>/dev/null
  "$relief" synth plane-waves -o "$tmp/ro/x.ply" --vertices 200 2>"$tmp/err"
  got=$?
  ok '[[ $got -eq 2 ]] && grep -q "Read-only file system" "$tmp/err" && [[ $(wc -l < "$tmp/err") -eq 1 ]]' \
     "a read-only file system: exit $got: $(cat "$tmp/err")"
  ok '[[ $(cat "$tmp/ro/x.ply") == "the user'"'"'s" ]]' "a file on a read-only file system changed"
  umount "$tmp/ro"
fi
echo "test_disk_full ($mode): $cases cases ($bad failed), $pass checks passed, $fail failed"
[[ $fail -eq 0 ]]
