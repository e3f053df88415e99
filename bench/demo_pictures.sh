#!/usr/bin/env bash
# Regenerate README's pictures of the demo (bench/figures/demo_*.png): the
# capture's front, the truth's back, and the completed back with the defaults
# and with --coherence 2. usage: bench/demo_pictures.sh [BUILD_DIR]   (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
relief=${1:-build}/relief
out=bench/figures
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$relief" synth cylinder-bark --colour --seed 1 -o "$tmp/capture.ply" --truth "$tmp/truth.ply"
"$relief" complete "$tmp/capture.ply" -o "$tmp/back.ply" --quiet
"$relief" complete "$tmp/capture.ply" -o "$tmp/back2.ply" --quiet --coherence 2
view() { "$relief" render "$1" -o "$out/$2" --view "$3" --size 320x300; }
view "$tmp/capture.ply" demo_captured.png 0,10
view "$tmp/truth.ply" demo_truth_back.png 180,10
view "$tmp/back.ply" demo_back.png 180,10
view "$tmp/back2.ply" demo_back_coherence2.png 180,10
