#!/usr/bin/env bash
# Configure and build the fuzz targets in BUILD_DIR (clang, Debug: -O1 -g with silt's debug
# assertions, AddressSanitizer, UBSan, libFuzzer coverage) and seed their corpora (seeds.sh).
# The build log goes to BUILD_DIR/build.log. Usage: tests/fuzz/build.sh BUILD_DIR
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1
cmake -S . -B "$out" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DSILT_FUZZ=ON \
  -DSILT_BUILD_TESTS=OFF -DSILT_BUILD_BENCH=OFF -DCMAKE_UNITY_BUILD=ON > /dev/null
targets=(command_parser_fuzz scene_fuzz checkpoint_fuzz session_fuzz repl_fuzz fuzz_seeds)
if ! cmake --build "$out" -j"$(nproc)" --target "${targets[@]}" > "$out/build.log" 2>&1; then
  tail -n 30 "$out/build.log"
  exit 1
fi
tests/fuzz/seeds.sh "$out"
