#!/usr/bin/env bash
# Build and run the benchmarks; figures go to stdout and CSV under OUT
# (default bench-out/). Both backends run side by side in one process.
#   bench/run.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-bench-out}
mkdir -p "$OUT"
./setup.sh deps
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELIEF_BUILD_BENCH=ON >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
if [[ ${1:-} == --quick ]]; then args=(--vertices 1000 --targets 4 --reps 3); else args=(--vertices 2000 --targets 8 --reps 5); fi
build/bench/bench_score "${args[@]}" --csv "$OUT/bench_score.csv"
