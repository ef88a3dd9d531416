#!/usr/bin/env bash
# Format and lint check of the C++ files a change touches: those changed in the last commit and
# those changed since it (staged or not). clang-format must leave them as they are; clang-tidy's
# checks (.clang-tidy) must find nothing. Needs a build directory with compile_commands.json.
# Also: the built silt holds no fused multiply-add (every vector level must give the same bits,
# core/simd_level.hpp; GCC 12 fuses some patterns for AVX-512 in spite of -ffp-contract=off).
# Usage: scripts/lint.sh [BUILD_DIR]      (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}
mapfile -t files < <({ git diff --name-only HEAD~1 HEAD 2>/dev/null || true; git diff --name-only HEAD; } |
                     sort -u | grep -E '\.(cpp|hpp)$' | while read -r f; do [ -f "$f" ] && echo "$f"; done)
if ! command -v objdump > /dev/null; then
  echo "lint: objdump (binutils) is missing: cannot check the build for fused multiply-adds"
  exit 1
fi
for bin in "$build_dir/silt" "$build_dir/tests/silt_tests"; do
  if [ ! -x "$bin" ]; then
    echo "lint: $bin is not built: cannot check it for fused multiply-adds"
    exit 1
  fi
  fused=$(objdump -d --no-show-raw-insn -C "$bin" |
          awk '/^[0-9a-f]+ <.*>:$/ { fn = $0 } /:[[:space:]]+(\{[a-z]+\} *)?vfn?m(add|sub)/ { print fn }' | sort -u)
  if [ -n "$fused" ]; then
    echo "lint: fused multiply-adds in $bin, in:"
    echo "$fused"
    exit 1
  fi
done
if [ ${#files[@]} -eq 0 ]; then
  echo "lint: no C++ file changed"
  exit 0
fi
echo "lint: ${#files[@]} file(s): clang-format"
clang-format --dry-run --Werror "${files[@]}"
mapfile -t sources < <(printf '%s\n' "${files[@]}" | grep -E '^(engine|shell|render)/.*\.cpp$' || true)
if [ ${#sources[@]} -gt 0 ]; then
  echo "lint: ${#sources[@]} source(s): clang-tidy"
  # clang-tidy exits non-zero when a check fired (WarningsAsErrors). The build is GCC's: flags
  # only GCC knows (-Wno-restrict) are not an error for clang.
  if ! out=$(printf '%s\0' "${sources[@]}" | xargs -0 -P"$(nproc)" -n4 clang-tidy -p "$build_dir" --quiet --extra-arg=-Wno-unknown-warning-option 2>&1); then
    echo "$out" | grep -vE '^[0-9]+ warnings? generated\.$|^Suppressed|^Use -header-filter'
    exit 1
  fi
fi
echo "lint: ok"
