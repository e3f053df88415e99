#!/usr/bin/env bash
# Build and run the whole default test suite (what CI runs, through .ci/run).
# Installs missing packages first when run as root. Slow tests are labelled
# `slow` and left out; run them with: ctest --test-dir build -L slow
#   ./test.sh            default suite
#   ./test.sh sanitize   the same under ASan + UBSan, in build-asan/, less the
#                        end-to-end completions (minutes each when sanitised;
#                        test_grow and test_score_opencl cover that code)
set -euo pipefail
cd "$(dirname "$0")"
./setup.sh deps
case "${1:-}" in
  sanitize) dir=build-asan; extra=(-DRELIEF_SANITIZE=ON -DRELIEF_BUILD_BENCH=OFF); skip='slow|end-to-end' ;;
  "") dir=build; extra=(); skip=slow ;;
  *) echo "usage: $0 [sanitize]" >&2; exit 1 ;;
esac
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "${extra[@]}" >/dev/null
cmake --build "$dir" -j"$(nproc)"
ctest --test-dir "$dir" --output-on-failure -j2 -LE "$skip"
