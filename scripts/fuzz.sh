#!/usr/bin/env bash
# Build the shell's command parser with libFuzzer (clang, AddressSanitizer, UBSan) and fuzz it for
# N seconds (default 20), starting from the shipped scripts. Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
out=build-fuzz
mkdir -p "$out/corpus"
clang++ -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I. -Iengine -Iengine/include tests/fuzz/command_parser_fuzz.cpp shell/command_parser.cpp engine/core/text.cpp \
  -o "$out/command_parser_fuzz"
# Seeds: every line of the shipped scripts.
n=0
for f in scenes/*.silt; do
  while IFS= read -r line; do
    printf '%s' "$line" > "$out/corpus/seed_$n"
    n=$((n + 1))
  done < "$f"
done
"$out/command_parser_fuzz" -max_total_time="$seconds" -max_len=256 -timeout=5 "$out/corpus" 2>&1 | tail -n 3
