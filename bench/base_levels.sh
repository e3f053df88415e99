#!/usr/bin/env bash
# relief complete --base smooth (issue 21) mono-scale against --levels 2 and
# 3 on holes cut where the truth is known from real scans that no
# primitive fits: the Max Planck bust (two balls), MeshLab's range map of a
# head (lato) and the Stanford bunny. Every run of a case in one script on
# one machine; per case and M: the targets' RMS distance to the truth
# (`relief eval --truth`; median, min and max over SEEDS seeds), its ratio
# to mono-scale's, the pattern-spectrum distance to the truth (lower is
# closer; the truth's own against the capture beside it), the median wall
# time and its ratio to mono-scale's, and level 1's search. CSV in OUT.
#   bench/base_levels.sh [CASE ...]   (default: all)
# Environment: OUT (default bench-out/base_levels), BUILD (default build),
# SEEDS (default 3), LEVELS (default "1 2 3 3c"; Mc: M levels with
# --search coherent, as mono-scale's auto takes on the larger captures),
# DATA (default ../shared/data).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench-out/base_levels}
BUILD=${BUILD:-build}
SEEDS=${SEEDS:-3}
LEVELS=${LEVELS:-1 2 3 3c}
DATA=${DATA:-../shared/data}
cmake --build "$BUILD" -j"${JOBS:-$(nproc)}" --target relief >/dev/null
relief=$BUILD/relief
mkdir -p "$OUT"
# name, scan, ball (centre x,y,z, radius; on the scan's surface)
cases=(
  "planck25 real/max_planck/decimated-max.obj 26.3,100,6.5,25"
  "planck40 real/max_planck/decimated-max.obj 26.3,100,6.5,40"
  "lato real/meshlab_rangemap_lato/lato000.ply 3.63,-28.88,-735.39,6"
  "bunny real/stanford_bunny/stanford-bunny.obj -0.03,0.08,0.05,0.015"
)
want=("$@")
csv=$OUT/base_levels.csv
echo "case,levels,seed,targets,seconds,truth_rms,spectrum,spectrum_truth,level1_search" > "$csv"
for c in "${cases[@]}"; do
  read -r name scan ball <<<"$c"
  if [[ ${#want[@]} -gt 0 && ! " ${want[*]} " =~ " $name " ]]; then continue; fi
  if [[ ! -f $DATA/$scan ]]; then echo "bench: $DATA/$scan missing, skipped"; continue; fi
  cap=$OUT/${name}_cut.ply truth=$OUT/${name}_truth.ply
  "$relief" cut "$DATA/$scan" -o "$cap" --truth "$truth" --ball "$ball" >/dev/null 2>&1
  for L in $LEVELS; do
    for ((seed = 1; seed <= SEEDS; ++seed)); do
      res=$OUT/${name}_L${L}_s$seed.ply rep=$OUT/${name}_L${L}_s$seed.json
      t0=$(date +%s.%N)
      search=()
      [[ $L == *c ]] && search=(--search coherent)
      "$relief" complete "$cap" -o "$res" --base smooth --levels "${L%c}" --seed "$seed" \
        "${search[@]}" --report "$rep" --quiet
      t1=$(date +%s.%N)
      ev=$("$relief" eval "$res" --truth "$truth")
      /usr/bin/python3 - "$rep" "$name" "$L" "$seed" "$t0" "$t1" "$ev" >> "$csv" <<'PY'
import json, re, sys
rep, name, L, seed, t0, t1, ev = sys.argv[1:]
r = json.load(open(rep))
rms = re.search(r"^truth_rms: (\S+)", ev, re.M).group(1)
m = re.search(r"^pattern_spectrum_distance: (\S+) \(truth's own: (\S+)\)", ev, re.M)
search = r["levels"][0]["search"] if r.get("levels") else r["growth_parameters"].get("search", "")
print("%s,%s,%s,%d,%.3f,%s,%s,%s,%s" % (name, L, seed, r["counts"]["targets"],
      float(t1) - float(t0), rms, m.group(1), m.group(2), search))
PY
    done
  done
done
/usr/bin/python3 - "$csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("%-9s %7s %2s %-22s %6s %-8s %8s %6s %s" % ("case", "targets", "M", "truth RMS med [min-max]",
      "/M1", "spectrum", "time_s", "/M1", "level-1 search"))
for case in dict.fromkeys(r["case"] for r in rows):
    base = None
    for L in dict.fromkeys(r["levels"] for r in rows if r["case"] == case):
        rs = [r for r in rows if r["case"] == case and r["levels"] == L]
        rms = [float(r["truth_rms"]) for r in rs]
        med, t = statistics.median(rms), statistics.median(float(r["seconds"]) for r in rs)
        spec = statistics.median(float(r["spectrum"]) for r in rs)
        if base is None:
            base = (med, t)
        print("%-9s %7s %2s %.4g [%.4g-%.4g] %6.2f %.3f (%s) %8.2f %6.2f %s" % (
            case, rs[0]["targets"], L, med, min(rms), max(rms), med / base[0], spec,
            rs[0]["spectrum_truth"], t, t / base[1], rs[0]["level1_search"]))
PY
echo "bench: $csv"
