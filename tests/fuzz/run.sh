#!/usr/bin/env bash
# Build the libFuzzer harnesses with clang and fuzz each for a bounded time.
#   tests/fuzz/run.sh BUILD_DIR SECONDS|runs=N [TARGET...]
# SECONDS: fuzz each target that long from a random seed, to find new bugs.
# runs=N: a bounded run instead (the default test suite's fuzz_short): seed
# 1, N executions per image and depth reader, N / 4 per mesh reader (OpenMesh
# and the repair on reading: some 600 a second), 30 N
# for the command line and N / 100 for
# the image fill, the occluders and the depth fill (each run a whole fill of up to 32 x 32
# pixels, some 5 to 10 a second under the coverage instrumentation), from the checked-in seeds
# and regressions only, so that the suite's verdict does not depend on the
# machine's speed or on earlier runs.
# TARGETs (default all): read_ply read_obj read_off read_stl read_image image_fill
# read_depth occluders depth_fill cli. Each starts from its working corpus in BUILD_DIR/corpus/TARGET
# (kept between runs), the seeds in tests/fuzz/corpus/TARGET and the inputs of
# past crashes in tests/fuzz/regressions/TARGET. A crash, leak, hang (10 s) or out-of-memory
# (2 GiB) leaves the input in BUILD_DIR/artifacts/TARGET/ and fails the run:
# fix it, then copy the input into tests/fuzz/regressions/TARGET/, which the
# normal test suite replays (fuzz_replay_TARGET). Exits 77 (skipped) when
# clang or its libFuzzer runtime is missing. Environment: JOBS (default 2).
set -euo pipefail
[[ $# -ge 2 ]] || { echo "usage: $0 BUILD_DIR SECONDS [TARGET...]" >&2; exit 1; }
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$1 secs=$2; shift 2
runs=
if [[ $secs == runs=* ]]; then runs=${secs#runs=}; fi
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(read_ply read_obj read_off read_stl read_image image_fill read_depth occluders depth_fill cli)

for cc in clang clang++; do
  command -v $cc >/dev/null || { echo "fuzz: $cc not found; skipped (setup.sh installs clang)"; exit 77; }
done
mkdir -p "$build"
probe=$build/probe.c
printf '#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n' > "$probe"
if ! clang -fsanitize=fuzzer,address,undefined "$probe" -o "$build/probe" 2>"$build/probe.log"; then
  echo "fuzz: clang cannot link -fsanitize=fuzzer (libclang-rt-dev missing?); skipped:"
  cat "$build/probe.log"
  exit 77
fi

# OSS-Fuzz's optimisation and debug level (-O1, line tables only): the
# build, most of fuzz_short's time, took 81 s instead of 99 s with -O2 -g
# (2 cores), and the runs as long (59 against 60 s); a crash's stack still
# names its lines.
fuzz_flags="-O1 -gline-tables-only -DNDEBUG"
cmake -S "$src" -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_FLAGS_RELWITHDEBINFO="$fuzz_flags" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$fuzz_flags" -DRELIEF_FUZZ=ON -DRELIEF_BUILD_TESTS=OFF \
  -DRELIEF_BUILD_BENCH=OFF -DRELIEF_WITH_OPENCL=OFF >/dev/null
cmake --build "$build" -j"${JOBS:-2}" --target $(printf 'fuzz_%s ' "${targets[@]}") >/dev/null

failed=()
for t in "${targets[@]}"; do
  case $t in
    cli) dict=(-dict="$src/tests/fuzz/cli.dict") ;;
    read_image) dict=(-dict="$src/tests/fuzz/image.dict") ;;
    read_depth) dict=(-dict="$src/tests/fuzz/depth.dict") ;;
    image_fill|occluders|depth_fill) dict=() ;; # a binary header: no words to offer
    *) dict=(-dict="$src/tests/fuzz/mesh.dict") ;;
  esac
  work=$build/corpus/$t art=$build/artifacts/$t log=$build/fuzz_$t.log
  if [[ -n $runs ]]; then
    n=$runs; [[ $t == cli ]] && n=$((runs * 30)); [[ $t == image_fill || $t == occluders || $t == depth_fill ]] && n=$((runs / 100))
    [[ $t == read_ply || $t == read_obj || $t == read_off || $t == read_stl ]] && n=$((runs / 4))
    bound=(-seed=1 -runs="$n")
    work=$build/corpus-repro/$t
    rm -rf "$work"
  else
    bound=(-max_total_time="$secs")
  fi
  mkdir -p "$work" "$art"
  dirs=("$work" "$src/tests/fuzz/corpus/$t")
  [[ -d $src/tests/fuzz/regressions/$t ]] && dirs+=("$src/tests/fuzz/regressions/$t")
  set +e
  "$build/tests/fuzz/fuzz_$t" "${bound[@]}" -timeout=10 -rss_limit_mb=2048 \
    -max_len=4096 ${dict[@]+"${dict[@]}"} -artifact_prefix="$art/" -close_fd_mask=3 \
    -print_final_stats=1 "${dirs[@]}" >"$log" 2>&1
  rc=$?
  set -e
  # The last status line: executions, coverage (edges), features, corpus.
  stats=$(grep -E '^#[0-9]+' "$log" | tail -1 | sed -E 's/ +(lim|exec\/s|rss|L|MS):.*//' || true)
  if [[ $rc -eq 0 ]]; then
    if [[ -n $runs ]]; then echo "fuzz_$t: seed 1, $n runs, ok: $stats"
    else echo "fuzz_$t: ${secs}s, ok: $stats"; fi
  else
    echo "fuzz_$t: FAILED (exit $rc): $stats"
    grep -E 'ERROR|SUMMARY|Test unit written' "$log" | head -5 | sed 's/^/  /'
    echo "  full log: $log"
    failed+=("$t")
  fi
done
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz: failed: ${failed[*]}; inputs in $build/artifacts/"
  exit 1
fi
