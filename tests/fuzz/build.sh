#!/usr/bin/env bash
# Configure BUILD_DIR as the sanitizer build (clang, Debug: -O1 -g1 with silt's debug assertions,
# AddressSanitizer, UBSan, libFuzzer coverage, unity sources), build its fuzz targets and seed
# their corpora (seeds.sh). The same directory then builds the unit tests and the benchmarks
# (scripts/test.sh), so the engine is compiled once for both. The build log goes to
# BUILD_DIR/build.log. Usage: tests/fuzz/build.sh BUILD_DIR
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1
# A directory configured before with another compiler (GCC) is configured afresh; its corpus stays.
if [ -f "$out/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$out/CMakeCache.txt"; then
  rm -rf "$out/CMakeCache.txt" "$out/CMakeFiles"
fi
cmake -S . -B "$out" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DSILT_FUZZ=ON -DSILT_SANITIZE=ON \
  -DSILT_BUILD_TESTS=ON -DSILT_BUILD_BENCH=ON -DCMAKE_UNITY_BUILD=ON > /dev/null
targets=(command_parser_fuzz scene_fuzz checkpoint_fuzz session_fuzz repl_fuzz fuzz_seeds)
if ! cmake --build "$out" -j"$(nproc)" --target "${targets[@]}" > "$out/build.log" 2>&1; then
  tail -n 30 "$out/build.log"
  exit 1
fi
tests/fuzz/seeds.sh "$out"
