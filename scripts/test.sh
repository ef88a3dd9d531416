#!/usr/bin/env bash
# Build silt (Release, warnings as errors), check the format and lint of the files the last change
# touched, run the unit tests, fuzz every input surface for 10 s each (scripts/fuzz.sh), then run
# the tests again under AddressSanitizer and UndefinedBehaviorSanitizer in the fuzzers' Debug build
# (clang, build-asan/: the engine compiled once for both), where the serial executor also checks
# every stage's access set; that build also compiles the benchmarks.
# Prints how long each part took.
# Usage: scripts/test.sh [--no-sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
part() { echo "test.sh: $1 done at $((SECONDS - start)) s"; }
scripts/setup.sh build -DSILT_WERROR=ON -DSILT_BUILD_BENCH=OFF
part "release build"
scripts/lint.sh build
ctest --test-dir build --output-on-failure -j"$(nproc)"
part "release tests"
scripts/fuzz.sh 10
part "fuzzing"
if [ "${1:-}" != "--no-sanitize" ]; then
  # Configured by the fuzzing above (tests/fuzz/build.sh). Warnings are the Release build's errors.
  cmake --build build-asan -j"$(nproc)"
  part "sanitizer build"
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j"$(nproc)" -LE long
  part "sanitizer tests"
fi
