#!/usr/bin/env bash
# Build and run the whole test suite (what CI runs, through .ci/run).
# Installs missing packages first when run as root. Slow tests are labelled
# `slow` and left out; run them with: ctest --test-dir build -L slow
#   ./test.sh            both passes below, default first
#   ./test.sh default    the Python package built into .venv (./setup.sh python),
#                        then the suite in build/, with its pytest tests, a short
#                        fuzzing run (build/fuzz, clang) and valgrind memcheck on
#                        one completion
#   ./test.sh sanitize   the suite again under ASan + UBSan, in build-asan/; its
#                        end-to-end completions take a 1000-vertex truth
#                        (plane-noise keeps 2000), the bark and the real scans'
#                        completions are left to the default pass, and the
#                        reruns that only compare backends' bytes run once
#                        (RELIEF_TEST_PASS=sanitize, tests/CMakeLists.txt)
set -euo pipefail
cd "$(dirname "$0")"
./setup.sh deps
suite() { # DIR CMAKE_OPTIONS...
  local dir=$1; shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
  cmake --build "$dir" -j"$(nproc)"
  ctest --test-dir "$dir" --output-on-failure -j2 -LE slow
}
# The sanitize build with line tables only (-g1): a report's stack still
# names file and line, and the build took 138 s instead of 177 s on 2 cores
# (OpenMesh's templates in host/mesh/io_openmesh.cpp 62 s instead of 80 s).
asan=(-DRELIEF_SANITIZE=ON -DRELIEF_BUILD_BENCH=OFF
      "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
      "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG")
case "${1:-}" in
  default) ./setup.sh python && suite build ;;
  sanitize) suite build-asan "${asan[@]}" ;;
  "") ./setup.sh python && suite build && suite build-asan "${asan[@]}" ;;
  *) echo "usage: $0 [default|sanitize]" >&2; exit 1 ;;
esac
