#!/usr/bin/env bash
# relief's mesh hole engines (complete told the hole and with defaults,
# depth-fill and complete-points --mesh told the hole) against CGAL's
# triangulate_refine_and_fair_hole, PyMeshLab's meshing_close_holes,
# pymeshfix and trimesh on cuts whose truth is known: a vase's wall, a
# statue's knee (two sizes), a sphere's cap, a notch at a range scan's
# border, a band all round a cylinder (issue 61). bench/mesh_holes.py says
# what is measured; docs/benchmarks.md has a run and the columns' meanings.
# The peers are pip packages in the bench's own venv (bench/.venv-mesh,
# git-ignored), run from Python, never linked.
#   bench/mesh_holes.sh [--quick] [--only CASE,...] [--timeout S] [--figures bench/figures]
# Environment: RELIEF (default build/relief; built when that is missing),
# OUT (default bench/out/mesh_holes), DATA (default ../shared/data),
# VENV (default bench/.venv-mesh), PYTHON (the venv's maker, default
# python3). A full run: about 10 minutes on 2 cores; --quick, 3 cuts: 2.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench/out/mesh_holes}
DATA=${DATA:-../shared/data}
VENV=${VENV:-bench/.venv-mesh}
if [[ -z ${RELIEF:-} ]]; then
  RELIEF=build/relief
  if [[ ! -x $RELIEF ]]; then
    cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
    cmake --build build -j"${JOBS:-$(nproc)}" --target relief >/dev/null
  fi
fi
[[ -x $RELIEF ]] || { echo "bench: no relief at $RELIEF" >&2; exit 1; }
PEERS="numpy scipy networkx cgal pymeshlab pymeshfix trimesh"
if ! "$VENV/bin/python" -c "import numpy, scipy, networkx, CGAL, pymeshlab, pymeshfix, trimesh" 2>/dev/null; then
  echo "bench: installing the peers into $VENV ($PEERS)"
  "${PYTHON:-python3}" -m venv "$VENV"
  "$VENV/bin/pip" install -q --upgrade pip >/dev/null
  # shellcheck disable=SC2086
  "$VENV/bin/pip" install -q $PEERS
fi
"$VENV/bin/python" -c "import CGAL, pymeshlab, pymeshfix, trimesh
from importlib.metadata import version as v
print('bench: peers: cgal %s, pymeshlab %s, pymeshfix %s, trimesh %s' % tuple(v(p) for p in ('cgal', 'pymeshlab', 'pymeshfix', 'trimesh')))"
mkdir -p "$OUT"
"$VENV/bin/python" bench/mesh_holes.py "$RELIEF" "$DATA" "$OUT" "$@"
