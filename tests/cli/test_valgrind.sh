#!/usr/bin/env bash
# valgrind memcheck on one whole completion: a small synthetic capture
# (synth --vertices 400, colour) completed with the scalar backend must run
# with no memory error and no definite or indirect leak, and give a mesh.
# Skips (77) without valgrind. Usage: test_valgrind.sh PATH/TO/relief
set -u
relief=$1
if ! command -v valgrind >/dev/null; then
  echo "valgrind not found; skipped (setup.sh installs it)"
  exit 77
fi
tmp=$(mktemp -d /tmp/relief-valgrind-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
"$relief" synth plane-waves --colour --seed 3 --vertices 400 -o "$tmp/capture.ply" || exit 1
# 99: valgrind found an error (kept apart from relief's own 0, 1 and 2).
valgrind --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect \
  --show-leak-kinds=definite,indirect --track-origins=yes \
  "$relief" complete "$tmp/capture.ply" -o "$tmp/completed.ply" --report "$tmp/report.json" \
  --backend scalar --quiet
rc=$?
if [[ $rc -ne 0 ]]; then
  echo "FAIL: valgrind/relief exit $rc (99: memcheck errors above)"
  exit 1
fi
if [[ ! -s $tmp/completed.ply || ! -s $tmp/report.json ]]; then
  echo "FAIL: no completed mesh or report"
  exit 1
fi
echo "valgrind memcheck clean: relief complete on a 400-vertex plane-waves capture"
