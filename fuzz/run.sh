#!/usr/bin/env bash
# Builds the job-file fuzzer (build-fuzz/, clang, libFuzzer + ASan + UBSan) and
# runs it for a bounded time: bash fuzz/run.sh [SECONDS] (default 60).
# The seed corpus is jobs/*.toml and fuzz/seeds/*; the inputs the fuzzer finds
# interesting go to build-fuzz/corpus/, kept between runs. A finding (crash,
# sanitizer report, an exception other than JobError/UsageError, an input slower
# than 10 s or using more than 2 GB) is written to build-fuzz/artifacts/ and the
# script exits non-zero: add the input as a regression test in tests/engine/job/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=build-fuzz

# Without Python: a fuzzed python_env job would import and call whatever its
# `factory` names (os:_exit among them), and CPython's allocations at exit read
# as leaks; the python_env table is tested in tests/python/test_python_env.py.
# A unity build, as CI's sanitizer build (.ci/run): 404 CPU-seconds against 577 for
# the fuzzer and the libraries (3 min 28 s against 4 min 55 s on 2 cores).
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_UNITY_BUILD=ON \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DGGK_BUILD_FUZZ=ON -DGGK_SANITIZE=ON -DGGK_BUILD_TESTS=OFF -DGGK_BUILD_BENCH=OFF \
  -DGGK_WITH_MPI=OFF -DGGK_WITH_PYTHON=OFF >/dev/null
cmake --build "$build" --target job_file_fuzzer -j "$(nproc)"

mkdir -p "$build/corpus" "$build/seeds" "$build/artifacts"
cp jobs/*.toml jobs/arenas/*.toml fuzz/seeds/* "$build/seeds/"

ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  "$build/fuzz/job_file_fuzzer" "$build/corpus" "$build/seeds" \
  -dict=fuzz/job_file.dict -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -max_len=65536 -artifact_prefix="$build/artifacts/" -print_final_stats=1
