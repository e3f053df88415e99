#!/usr/bin/env bash
# The hole model on real photogrammetry (issue 40): a ball cut in a vase's
# wall and in the statue's knee (ggg_sfm), completed by complete-points with
# default options. The cut's rim is filled and the new points stay at the
# cut and the capture's own small holes; the vase's mouth (an outer border)
# and its open base, and the statue's open plinth (wider than max_hole) are
# listed and left open; nothing to fill exits 1 naming the max_hole that
# would fill the widest rim, with no output. depth-fill on a mesh fills the
# same holes and leaves the same openings.
#   test_ggg_holes.sh PATH/TO/relief DATA_DIR (../shared/data) [sanitize]
# sanitize (the ASan + UBSan pass): the longest runs, complete's growth on
# the statue, the pot's flutes and depth-fill on the statue (24 s under
# ASan), are left to the default pass (the growth and depth-fill run under
# the sanitizers on the other cases), and depth-fill on the vase runs at
# half the default resolution.
set -u
relief=$1 data=$2/real/ggg_sfm full=1 here=$(cd "$(dirname "$0")" && pwd)
[[ ${3:-} == sanitize ]] && full=0
tmp=$(mktemp -d /tmp/relief-ggg-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
. "$(dirname "$0")/../cli/expect.sh" # expect, ok
[[ -f $data/blackVase.ply && -f $data/Angel.ply ]] || { echo "$data: not found: skipped"; exit 77; }

# fate NAME JSON CX CY CZ: the fate of the rim whose centre is nearest (CX, CY, CZ)
fate() {
  python3 - "$1" "$2" "$3" "$4" <<'PY'
import json, math, sys
r = json.load(open(sys.argv[1]))
holes = (r["holes"] if "holes" in r else r["hole_model"])["list"]
c = [float(x) for x in sys.argv[2:5]]
h = min(holes, key=lambda h: math.dist(h["centre"], c))
print(h["fate"] if math.dist(h["centre"], c) < 40 else "none")
PY
}

# boundary FILE CX CY CZ R: the number of boundary loops whose centres lie
# within R of (CX, CY, CZ), the longest loop's edges, the vertex count and
# the number of loops.
boundary() {
  python3 - "$@" <<'PY'
import math, struct, sys
f = open(sys.argv[1], "rb"); head = []
while not head or head[-1] != b"end_header":
    head.append(f.readline().strip())
el, props = None, {}
for l in head:
    w = l.split()
    if w[:1] == [b"element"]:
        el = w[1].decode(); props[el] = [int(w[2]), []]
    elif w[:1] == [b"property"]:
        props[el][1].append(w[1:])
code = {b"float": "f", b"double": "d", b"uchar": "B", b"int": "i"}
nv, vp = props["vertex"]
fmt = "<" + "".join(code[p[0]] for p in vp)
pos = [struct.unpack(fmt, f.read(struct.calcsize(fmt)))[:3] for _ in range(nv)]
edges = {}
for _ in range(props["face"][0]):
    n = f.read(1)[0]
    t = struct.unpack("<%di" % n, f.read(4 * n))
    for i in range(n):
        e = tuple(sorted((t[i], t[(i + 1) % n])))
        edges[e] = edges.get(e, 0) + 1
parent = {}
def root(x):
    while parent.setdefault(x, x) != x:
        parent[x] = parent[parent[x]]; x = parent[x]
    return x
bd = [e for e, k in edges.items() if k == 1]
for a, b in bd:
    parent[root(a)] = root(b)
loops = {}
for a, b in bd:
    loops.setdefault(root(a), []).append(a)
c, r = [float(x) for x in sys.argv[2:5]], float(sys.argv[5])
near = sum(1 for l in loops.values()
           if math.dist([sum(pos[v][k] for v in l) / len(l) for k in range(3)], c) < r)
print(near, max((len(l) for l in loops.values()), default=0), nv, len(loops))
PY
}

# new_points FILE CONDITION: how many of the PLY's new vertices (label 1)
# meet CONDITION, a Python expression in x, y, z (and math).
new_points() {
  PYTHONPATH="$here" python3 - "$1" "$2" <<'PY'
import math, sys
from ply_vertices import vertices
test = compile(sys.argv[2], "condition", "eval")
print(sum(v["label"] == 1 and bool(eval(test, {"math": math}, v)) for v in vertices(sys.argv[1])))
PY
}

# The vase: the cut at the widest part of its wall; the mouth at the top
# (z about 280 to 400), the base at z 17.
"$relief" cut "$data/blackVase.ply" --ball 148.82,20.99,223.15,30 -o "$tmp/vase.ply" 2>/dev/null || exit 2
# One run gives the points and the surface (--mesh adds the surface and
# changes neither the points nor the holes' fates).
expect 0 "left open" -- "$relief" complete-points "$tmp/vase.ply" -o "$tmp/vase_p.ply" --mesh "$tmp/vase_m.ply" --report "$tmp/vase_m.json" --iterations 2
ok '[[ $(fate "$tmp/vase_m.json" 148.8 21 223) == filled ]]' "the vase's cut is not filled: $(fate "$tmp/vase_m.json" 148.8 21 223)"
ok '[[ $(fate "$tmp/vase_m.json" 4 8 17) == too_large ]]' "the vase's base is not left open as too large: $(fate "$tmp/vase_m.json" 4 8 17)"
ok '[[ $(fate "$tmp/vase_m.json" -6 -3 279) == border ]]' "the vase's mouth is not left open as a border: $(fate "$tmp/vase_m.json" -6 -3 279)"
# No new point in the mouth or the base: none above the rim's lowest point
# outside the capture's small holes, none below z 30.
low=$(new_points "$tmp/vase_p.ply" "z < 30")
ok '[[ $low == 0 ]]' "new points in the vase's open base: ${low:-the output could not be read}"

# The surface (--mesh): the filled holes' loops are closed, not only
# filled with points. The capture has 257 boundary loops and 250 of them
# are holes; the patches left 262 open (their own rims besides) before the
# gaps along them were closed (issue 40: holes left where relief said it
# completed); what stays open is counted in the report (mesh.open_loops).
read -r _ _ _ loops <<<"$(boundary "$tmp/vase_m.ply" 0 0 0 0)"
ok '[[ -n $loops && $loops -le 60 ]]' "the vase's completed surface has ${loops:-no count of} open loops (60 at most: its 7 open borders and openings, and under 50 gaps)"
ok 'grep -q "\"open_loops\": [0-9]" "$tmp/vase_m.json"' "the report does not count the loops left open"

# The statue: the cut at its knee; the plinth's open bottom at z -112.
"$relief" cut "$data/Angel.ply" --ball 13.11,-64.51,16.35,15 -o "$tmp/angel.ply" 2>/dev/null || exit 2
expect 0 "1 opening(s) wider than max_hole" -- "$relief" complete-points "$tmp/angel.ply" -o "$tmp/angel_out.ply" --report "$tmp/angel.json" --iterations 2
ok '[[ $(fate "$tmp/angel.json" 13.1 -64.5 16.4) == filled ]]' "the statue's cut is not filled"
ok '[[ $(fate "$tmp/angel.json" 0 9 -112) == too_large ]]' "the statue's plinth is not left open"

# complete on the same cut, default options: the statue fits no primitive,
# so it grows on its smoothed base; the cut filled, the plinth open. Its
# 18 329 samples x 4 rotations x 875 targets (6.4e7) are past search
# auto's bound (2.5e7), so the search is coherent: the exhaustive one took
# 77 s here (issue 40: every ggg cut within a minute), the coherent 13 s.
if [[ $full == 1 ]]; then
expect 0 "" -- "$relief" complete "$tmp/angel.ply" -o "$tmp/angel_c.ply" --report "$tmp/angel_c.json" --quiet
ok '[[ $(fate "$tmp/angel_c.json" 13.1 -64.5 16.4) == filled ]]' "complete did not fill the statue's cut"
ok '[[ $(fate "$tmp/angel_c.json" 0 9 -112) == too_large ]]' "complete did not leave the statue's plinth open"
ok 'grep -q "\"search\": \"coherent\"" "$tmp/angel_c.json"' "complete searched the statue exhaustively (a minute and more)"
fi

# A cut that reaches the capture's border (issue 40: the statue's drapery
# cut through to its border was left open with exit 0): a ball at the
# plinth's front edge merges with the plinth's open bottom into one loop,
# which the model leaves open (too large). A hole mask at the cut fills
# that loop in part, only its rim points within the mask: the new points
# stay at the cut and the plinth's bottom stays open. depth-fill closes
# the same notch (issue 61: it refused, having no closed rim to zip its
# skin to): its arc of the loop and the chord between the arc's ends.
"$relief" cut "$data/Angel.ply" --ball 26.75,-68.85,-100,15 -o "$tmp/edge.ply" 2>/dev/null || exit 2
expect 0 "" -- "$relief" complete-points "$tmp/edge.ply" -o "$tmp/edge_o.ply" --report "$tmp/edge.json" --iterations 2 --quiet
ok '[[ $(fate "$tmp/edge.json" 2 4 -111) == too_large ]]' "the cut merged with the plinth's border is not left open by default: $(fate "$tmp/edge.json" 2 4 -111)"
expect 0 "" -- "$relief" complete-points "$tmp/edge.ply" -o "$tmp/edge_m.ply" --mesh "$tmp/edge_mm.ply" --report "$tmp/edge_m.json" --hole-mask ball:26.75,-68.85,-100,18 --iterations 2 --quiet
ok 'grep -q "\"in_part\": true" "$tmp/edge_m.json" && [[ $(fate "$tmp/edge_m.json" 29.6 -62.4 -102.2) == filled ]]' "the mask did not fill the border's loop in part at the cut"
far="$(new_points "$tmp/edge_m.ply" True) $(new_points "$tmp/edge_m.ply" "math.dist((x, y, z), (26.75, -68.85, -100)) > 40")"
ok '[[ ${far% *} -gt 50 && ${far#* } == 0 ]]' "the in-part fill: ${far% *} new points, ${far#* } over 40 from the cut (the plinth's bottom capped?)"
read -r plinth longest _ <<<"$(boundary "$tmp/edge_mm.ply" 0 9 -112 60)"
ok '[[ $plinth -ge 1 && $longest -ge 150 ]]' "the plinth's bottom is not left open by the in-part fill: ${plinth:-?} loops there, the longest ${longest:-?} edges"
expect 0 "" -- "$relief" depth-fill "$tmp/edge.ply" -o "$tmp/edge_d.ply" --hole-mask ball:26.75,-68.85,-100,18 --resolution 96 --quiet
far="$(new_points "$tmp/edge_d.ply" True) $(new_points "$tmp/edge_d.ply" "math.dist((x, y, z), (26.75, -68.85, -100)) > 40")"
ok '[[ ${far% *} -gt 20 && ${far#* } == 0 ]]' "depth-fill's notch: ${far% *} new vertices, ${far#* } over 40 from the cut"
read -r plinth longest _ <<<"$(boundary "$tmp/edge_d.ply" 0 9 -112 60)"
ok '[[ $plinth -ge 1 && $longest -ge 150 ]]' "depth-fill's notch closed the plinth's bottom: ${plinth:-?} loops there, the longest ${longest:-?} edges"

# Nothing to fill: every rim wider than a tiny max_hole.
expect 1 "nothing to fill" -- "$relief" complete-points "$tmp/angel.ply" -o "$tmp/bad.ply" --max-hole 0.001
ok 'grep -q "too_large rim of [0-9]* points.*: max_hole [0-9.e+]* or hole_ball" "$tmp/err"' "the refusal does not say what would fill the widest rim"
ok '[[ ! -e "$tmp/bad.ply" ]]' "output left behind when nothing is filled"
# A hole mask selects: the plinth filled, the knee's cut left open.
expect 0 "not selected" -- "$relief" complete-points "$tmp/angel.ply" -o "$tmp/sel.ply" --report "$tmp/sel.json" --hole-mask ball:0,9,-112,100 --iterations 2 --geometry-only
ok '[[ $(fate "$tmp/sel.json" 0 9 -112) == filled && $(fate "$tmp/sel.json" 13.1 -64.5 16.4) == not_selected ]]' "the hole mask did not select the plinth alone"

# depth-fill on a mesh (issue 40): the capture with the cut filled, not a
# solid. Six depth images make a closed volume of anything (the vase came
# back full, its mouth capped, 981 380 vertices); by default now the
# solid's skin over each filled hole is zipped into the capture, and the
# mouth, the base and the plinth stay open.
# The sanitize pass at half the default resolution (128 voxels along the
# box, the same path: 9 s under ASan against 25 s).
res=()
[[ $full == 1 ]] || res=(--resolution 128)
expect 0 "" -- "$relief" depth-fill "$tmp/vase.ply" -o "$tmp/vase_d.ply" --report "$tmp/vase_d.json" "${res[@]}" --quiet
read -r cut longest nv _ <<<"$(boundary "$tmp/vase_d.ply" 148.8 21 223 40)"
read -r base _ _ <<<"$(boundary "$tmp/vase_d.ply" 4 8 17 40)"
ok '[[ $cut == 0 ]]' "depth-fill left ${cut:-?} loops open at the vase's cut"
ok '[[ $longest -ge 1000 && $base -ge 1 ]]' "depth-fill closed the vase's mouth (its longest loop: ${longest:-?} edges) or its base (${base:-?} loops there)"
ok '[[ $nv -lt 40000 ]]' "depth-fill returned a solid, not the vase: $nv vertices"
ok 'grep -q "\"holes_patched\": [1-9]" "$tmp/vase_d.json" && grep -q "\"fate\": \"border\"" "$tmp/vase_d.json"' "the depth-fill report lacks its patches or the mouth's fate"
if [[ $full == 1 ]]; then # the vase's run above shows this path to the sanitizers
expect 0 "" -- "$relief" depth-fill "$tmp/angel.ply" -o "$tmp/angel_d.ply" --quiet
read -r cut _ _ <<<"$(boundary "$tmp/angel_d.ply" 13.1 -64.5 16.4 20)"
read -r plinth _ _ <<<"$(boundary "$tmp/angel_d.ply" 0 9 -112 60)"
ok '[[ $cut == 0 && $plinth -ge 1 ]]' "depth-fill on the statue: ${cut:-?} loops open at the knee's cut, ${plinth:-?} at the plinth (1 wanted)"
fi
expect 0 "" -- "$relief" depth-fill "$tmp/vase.ply" -o "$tmp/vase_s.ply" --solid --resolution 96 --quiet
read -r _ longest _ <<<"$(boundary "$tmp/vase_s.ply" 0 0 0 1)"
ok '[[ $longest == 0 ]]' "depth-fill --solid is not closed: a loop of $longest edges"
# The fluted pot (issue 40: its flutes must continue): a ball that takes
# the outer face of its thin wall only (the inner face is captured too).
# depth-fill's patch follows the flutes: at each new vertex on the outer
# wall, its radius about the pot's axis against the truth's at the same
# angle and height, both less their means, correlate (0.83 here with the
# solid's skin; 0.76 with the faired patch of issue 61, which takes the
# capture's density: 22 vertices on the wall where the skin had the
# voxels', over 200) and differ by about the flutes' own spread (RMS 2.2,
# the truth's SD 2.0).
# complete and complete-points do not (correlation 0.06: the base's
# implicit surface wanders between the two faces; README).
if [[ $full == 1 ]]; then
"$relief" cut "$data/plasticVase.ply" --ball 207.04,-4.97,274.94,36 -o "$tmp/pot.ply" --truth "$tmp/pot_t.ply" 2>/dev/null || exit 2
expect 0 "" -- "$relief" depth-fill "$tmp/pot.ply" -o "$tmp/pot_d.ply" --quiet
read -r n corr rms sd <<<"$(PYTHONPATH="$here" python3 - "$tmp/pot_t.ply" "$tmp/pot_d.ply" <<'PY'
import math, sys
from ply_vertices import vertices as read
c, R = (177.05, -4.25, 274.94), 22.0
rc = math.hypot(c[0], c[1])
def cyl(v): return (math.atan2(v["y"], v["x"]), math.hypot(v["x"], v["y"]), v["z"])
def near(v, r): return math.dist((v["x"], v["y"], v["z"]), c) < r
truth = [cyl(v) for v in read(sys.argv[1]) if near(v, R + 10)]
truth = [t for t in truth if t[1] > rc - 4]  # the outer face
new = [cyl(v) for v in read(sys.argv[2]) if v.get("label") == 1 and near(v, R)]
pairs = []
for a, r, z in (v for v in new if v[1] > rc - 4):
    t = sorted(truth, key=lambda t: ((t[0] - a) * rc) ** 2 + (t[2] - z) ** 2)[:3]
    pairs.append((r, sum(q[1] for q in t) / 3))
if len(pairs) < 10:
    print(len(pairs), 0, 99, 1); sys.exit()
ma, mb = (sum(p[k] for p in pairs) / len(pairs) for k in (0, 1))
sab = sum((p[0] - ma) * (p[1] - mb) for p in pairs)
saa, sbb = (sum((p[k] - m) ** 2 for p in pairs) for k, m in ((0, ma), (1, mb)))
print(len(pairs), "%.3f" % (sab / math.sqrt(saa * sbb)),
      "%.3f" % math.sqrt(sum((p[0] - p[1]) ** 2 for p in pairs) / len(pairs)),
      "%.3f" % math.sqrt(sbb / len(pairs)))
PY
)"
ok 'python3 -c "import sys; sys.exit(not ($n >= 15 and $corr >= 0.6 and $rms <= 1.5 * $sd))"' "depth-fill does not continue the pot's flutes: ${n:-?} new vertices on the wall, correlation ${corr:-?} with the truth's radius (0.6 wanted), RMS ${rms:-?} against the flutes' SD ${sd:-?}"
fi
expect 1 "nothing to fill" -- "$relief" depth-fill "$tmp/vase.ply" -o "$tmp/bad.ply" --hole-mask ball:0,0,1000,1
ok '[[ ! -e "$tmp/bad.ply" ]]' "output left behind when depth-fill fills nothing"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
