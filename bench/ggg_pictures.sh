#!/usr/bin/env bash
# The README's pictures of issue 40 (real captures as they come): a hole cut
# in each ggg_sfm photogrammetry capture (a vase's wall, the fluted pot's,
# the statue's knee), completed by `relief complete`, `relief
# complete-points` and `relief depth-fill` with default options: the repair
# on reading, the hole
# model (the cut filled; the vase's mouth and base, the statue's plinth left
# open), rendered with the new vertices orange.
#   bench/ggg_pictures.sh [BUILD_DIR] [DATA_DIR]     (writes bench/figures/ggg_*.png)
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
relief=${1:-$src/build}/relief
data=${2:-$src/../shared/data}/real/ggg_sfm
out=$src/bench/figures
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# name, file, the cut's ball, the view
cases=("vase blackVase 148.82,20.99,223.15,30 0,10"
       "pot plasticVase 177.05,-4.25,274.94,30 0,10"
       "angel Angel 13.11,-64.51,16.35,15 -90,10")
for c in "${cases[@]}"; do
  read -r name file ball view <<<"$c"
  "$relief" cut "$data/$file.ply" --ball "$ball" -o "$tmp/$name.ply" 2>/dev/null
  /usr/bin/time -f "$name complete: %e s" "$relief" complete "$tmp/$name.ply" -o "$tmp/${name}_c.ply" --quiet
  /usr/bin/time -f "$name complete-points: %e s" "$relief" complete-points "$tmp/$name.ply" \
    -o "$tmp/${name}_p.ply" --mesh "$tmp/${name}_pm.ply" --quiet
  /usr/bin/time -f "$name depth-fill: %e s" "$relief" depth-fill "$tmp/$name.ply" -o "$tmp/${name}_d.ply" --quiet
  "$relief" render "$tmp/${name}_d.ply" -o "$out/ggg_${name}_depth.png" --colour-by label \
    --view "$view" --size 360x360 >/dev/null 2>&1
  "$relief" render "$tmp/$name.ply" -o "$out/ggg_${name}_cut.png" --view "$view" --size 360x360 >/dev/null 2>&1
  "$relief" render "$tmp/${name}_c.ply" -o "$out/ggg_${name}_complete.png" --colour-by label \
    --view "$view" --size 360x360 >/dev/null 2>&1
  "$relief" render "$tmp/${name}_pm.ply" -o "$out/ggg_${name}_points.png" --colour-by label \
    --view "$view" --size 360x360 >/dev/null 2>&1
done
# A cut at the statue's plinth edge, merged with the plinth's open bottom
# into one loop: filled in part by a hole mask (complete-points --mesh),
# the plinth left open; both cropped about the cut.
edge=26.75,-68.85,-100
"$relief" cut "$data/Angel.ply" --ball $edge,15 -o "$tmp/edge.ply" 2>/dev/null
"$relief" complete-points "$tmp/edge.ply" -o "$tmp/edge_p.ply" --mesh "$tmp/edge_m.ply" \
  --hole-mask ball:$edge,18 --quiet
# crop IN OUT: IN's vertices within 45 of the cut and the triangles among
# them, every property kept (relief cut --crop writes no labels).
crop() {
  python3 - "$1" "$2" <<'PY'
import struct, sys
c, r = (26.75, -68.85, -100.0), 45.0
f = open(sys.argv[1], "rb"); head = b""
while not head.endswith(b"end_header\n"):
    head += f.readline()
h = head.decode()
nv = int(h.split("element vertex ")[1].split()[0])
nf = int(h.split("element face ")[1].split()[0])
props = [l.split() for l in h.splitlines() if l.startswith("property") and "list" not in l]
fmt = "<" + "".join({"float": "f", "double": "d", "int": "i", "uchar": "B"}[p[1]] for p in props)
raw = [f.read(struct.calcsize(fmt)) for _ in range(nv)]
keep = [sum((a - b) ** 2 for a, b in zip(struct.unpack(fmt, x)[:3], c)) <= r * r for x in raw]
faces = []
for _ in range(nf):
    n = f.read(1)[0]
    faces.append(struct.unpack("<%di" % n, f.read(4 * n)))
idx = {}
for i, k in enumerate(keep):
    if k:
        idx[i] = len(idx)
faces = [t for t in faces if all(keep[i] for i in t)]
o = open(sys.argv[2], "wb")
o.write(h.replace("element vertex %d" % nv, "element vertex %d" % len(idx))
         .replace("element face %d" % nf, "element face %d" % len(faces)).encode())
o.write(b"".join(x for x, k in zip(raw, keep) if k))
for t in faces:
    o.write(struct.pack("<B%di" % len(t), len(t), *[idx[i] for i in t]))
PY
}
crop "$tmp/edge.ply" "$tmp/edge_x.ply"
crop "$tmp/edge_m.ply" "$tmp/edge_mx.ply"
"$relief" render "$tmp/edge_x.ply" -o "$out/ggg_edge_cut.png" --view -90,10 --size 300x300 >/dev/null 2>&1
"$relief" render "$tmp/edge_mx.ply" -o "$out/ggg_edge_points.png" --colour-by label \
  --view -90,10 --size 300x300 >/dev/null 2>&1
echo "pictures in $out/ggg_*.png"
