#!/usr/bin/env bash
# Same bytes from two builds of relief: every command of a stated set, run
# by OLD and by NEW on the same inputs, must write identical outputs (meshes,
# images, depth frames, point sets, eval/fit JSON). Reports are left out:
# they hold timings. Used to show a refactoring changed nothing a user sees
# (issue 39); not part of the default suite (it needs two builds).
#   tests/cli/same_bytes.sh OLD/relief NEW/relief BUILD_DIR [DATA_DIR]
# BUILD_DIR holds NEW's tests/image_tool and tests/depth_tool (the inputs).
# ONLY=REGEX runs the cases whose names match (e.g. ONLY='image|depth').
# PNG_PIXELS=1 compares PNG outputs by their pixels (image_tool same) when
# their bytes differ: for two builds with different PNG writers.
set -u
old=$1 new=$2 build=$3 data=${4:-$(cd "$(dirname "$0")/../../.." && pwd)/shared/data}
tmp=$(mktemp -d /tmp/relief-same-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
itool=$build/tests/image_tool dtool=$build/tests/depth_tool
mkdir -p "$tmp/in" "$tmp/old" "$tmp/new"
in=$tmp/in
pass=0 fail=0

# Inputs, made once by NEW (synth and cut are themselves compared below).
"$new" synth cylinder-bark --colour --seed 1 --vertices 1500 -o "$in/bark.ply" --truth "$in/bark_truth.ply" 2>/dev/null
"$new" cut "$data/real/fertility/fertility.off" -o "$in/fert_cut.ply" --truth "$in/fert_truth.ply" --ball 5.48,31.18,10.73,8 2>/dev/null
"$itool" mask "$in/m.png" 512 512 224 224 48 48
"$itool" mask "$in/cm.png" 451 300 200 120 40 30
"$dtool" crop "$data/depth/office1.pcd" 0 0 240 180 "$in/office.pcd"
"$itool" mask "$in/dm.png" 240 180 150 100 20 16
"$dtool" crop "$data/depth/motorcycle_disp.pfm" 300 200 200 150 "$in/moto.pfm"
"$dtool" png16 "$in/office.pcd" 5000 "$in/office.png"
"$new" cut "$data/real/bennu_radar/bennu.obj" -o "$in/bennu_cut.ply" --ball 0,0,0.25,0.08 2>/dev/null

# NAME OUTPUT-FILES... -- ARGS: run ARGS by both, with @ in ARGS and in the
# output names standing for the build's own output folder.
run() {
  local name=$1; shift
  [[ -n ${ONLY:-} && ! $name =~ $ONLY ]] && return 0
  local outs=()
  while [[ $1 != -- ]]; do outs+=("$1"); shift; done
  shift
  for who in old new; do
    local bin=${!who} args=()
    for a in "$@"; do args+=("${a//@/$tmp/$who}"); done
    "$bin" "${args[@]}" > "$tmp/$who/$name.stdout" 2> "$tmp/$who/$name.stderr"
    echo $? > "$tmp/$who/$name.rc"
  done
  local bad=""
  cmp -s "$tmp/old/$name.rc" "$tmp/new/$name.rc" || bad="exit $(cat "$tmp/old/$name.rc") -> $(cat "$tmp/new/$name.rc")"
  for o in "${outs[@]}"; do
    [[ -e $tmp/old/$o ]] || { bad+=" $o: OLD wrote none"; continue; }
    cmp -s "$tmp/old/$o" "$tmp/new/$o" && continue
    # PNG_PIXELS=1: a PNG of the same pixels is the same (for builds whose
    # PNG writers differ; otherwise other bytes are a difference).
    if [[ ${PNG_PIXELS:-0} == 1 && $o == *.png ]] && "$itool" same "$tmp/old/$o" "$tmp/new/$o"; then
      echo "  $o: the same pixels, other bytes"
      continue
    fi
    bad+=" $o differs"
  done
  if [[ -z $bad ]]; then
    pass=$((pass + 1)); echo "same: $name"
  else
    fail=$((fail + 1)); echo "DIFFERENT: $name:$bad"
  fi
}

run synth bark.ply bark_t.ply -- synth cylinder-bark --colour --seed 1 --vertices 1500 -o @/bark.ply --truth @/bark_t.ply
run cut cut.ply cut_t.ply -- cut "$data/real/fertility/fertility.off" -o @/cut.ply --truth @/cut_t.ply --ball 5.48,31.18,10.73,8
run fit fit.stdout -- fit "$in/bark.ply" --json
run smooth smooth.ply -- smooth "$in/bark.ply" -o @/smooth.ply --quiet
run complete_scalar c_scalar.ply -- complete "$in/bark.ply" -o @/c_scalar.ply --backend scalar --quiet
run complete_host c_host.ply -- complete "$in/bark.ply" -o @/c_host.ply --backend host --quiet
run complete_opencl c_opencl.ply -- complete "$in/bark.ply" -o @/c_opencl.ply --backend opencl --quiet
run complete_coherent c_coh.ply -- complete "$in/bark.ply" -o @/c_coh.ply --search coherent --seed 3 --quiet
run complete_levels c_l2.ply -- complete "$in/bark.ply" -o @/c_l2.ply --levels 2 --backend host --quiet
run complete_levels_opencl c_l2cl.ply -- complete "$in/bark.ply" -o @/c_l2cl.ply --levels 2 --backend opencl --quiet
run complete_base_smooth c_bs.ply -- complete "$in/fert_cut.ply" -o @/c_bs.ply --base smooth --backend host --quiet
run complete_base_smooth_levels c_bs2.ply -- complete "$in/fert_cut.ply" -o @/c_bs2.ply --base smooth --levels 2 --backend host --quiet
run eval_json eval_json.stdout -- eval "$in/bark.ply" --truth "$in/bark_truth.ply" --json
run render render.png -- render "$in/bark.ply" -o @/render.png --size 200x150
run image_fill_scalar if.png -- image-fill "$data/images/brick.png" --mask "$in/m.png" -o @/if.png --backend scalar --quiet
run image_fill_opencl if_cl.png -- image-fill "$data/images/brick.png" --mask "$in/m.png" -o @/if_cl.png --backend opencl --quiet
run image_fill_windows ifa.png -- image-fill "$data/images/chelsea.png" --mask "$in/cm.png" -o @/ifa.png --window 33 --min-window 9 --seed 4 --quiet
run image_fill_bad_mask -- image-fill "$data/images/chelsea.png" --mask "$in/m.png" -o @/bad.png
run depth_fill_plain dp.pcd dp.ply -- depth-fill "$in/office.pcd" --mask "$in/dm.png" -o @/dp.pcd --points @/dp.ply --variant plain --backend scalar --quiet
run depth_fill_haar dh.pcd -- depth-fill "$in/office.pcd" --mask "$in/dm.png" -o @/dh.pcd --variant haar --backend scalar --quiet
run depth_fill_decompose dd.pcd -- depth-fill "$in/office.pcd" --mask "$in/dm.png" -o @/dd.pcd --backend opencl --quiet
run depth_fill_pfm dpfm.pfm -- depth-fill "$in/moto.pfm" -o @/dpfm.pfm --quiet
run depth_fill_png dpng.png -- depth-fill "$in/office.png" --mask "$in/dm.png" -o @/dpng.png --quiet
run depth_fill_mesh dmesh.ply -- depth-fill "$in/bennu_cut.ply" -o @/dmesh.ply --resolution 48 --quiet
run points cp.ply cpm.ply -- complete-points "$in/fert_cut.ply" -o @/cp.ply --mesh @/cpm.ply --iterations 10 --quiet
run points_brute_opencl cpb.ply -- complete-points "$in/fert_cut.ply" -o @/cpb.ply --iterations 5 --grid-search brute --backend opencl --quiet
run points_pcd cpp.ply -- complete-points "$data/points/milk_color.pcd" -o @/cpp.ply --iterations 5 --quiet
run bad_window -- complete "$in/bark.ply" -o @/bad.ply --window 99

echo "same_bytes: $pass same, $fail different"
[[ $fail -eq 0 ]]
