#!/usr/bin/env bash
# Build the libFuzzer targets of tests/fuzz (clang, AddressSanitizer, UBSan, in build-asan/, the
# test script's sanitizer build) and fuzz each for N seconds (default 20), one after the other on
# one core, from the shipped files and what earlier runs found (build-asan/corpus/): the shell's
# command parser, scene files, checkpoints, and shell sessions without and with a terminal. Prints
# one line per target, and what went wrong; exits non-zero on any crash, leak, timeout,
# out-of-memory or sanitizer report (the input in build-asan/artifacts/, the log in
# build-asan/logs/). Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
# These short runs look for memory and undefined-behaviour errors; the stages' access check
# (on in this build, run by the unit tests) is left to the long runs of bench/fuzz_all.sh.
export SILT_ACCESS_CHECK=0
seconds=${1:-20}
out=build-asan
tests/fuzz/build.sh "$out"
failed=0
# A failed run of target T: its log and the lines that tell what broke.
report() {
  echo "fuzz $1: FAILED$2, log $3"
  { grep -E '^Running: ' "$3" | tail -n 1 || true; } # a replay: the input that broke
  grep -E 'ERROR:|runtime error:|silt fuzz:|^ +#[0-3] |SUMMARY:|Test unit written' "$3" | cut -c1-200 | head -n 12 || true
  failed=1
}
# First the inputs the targets found (tests/fuzz/crashes/, by extension), each target's in one
# process in name order: some broke silt only after an earlier input's state.
declare -A found=([scene]=toml [checkpoint]=ckpt [session]=session [repl]=keys)
shopt -s nullglob
for t in scene checkpoint session repl; do
  files=(tests/fuzz/crashes/*."${found[$t]}")
  [ ${#files[@]} -gt 0 ] || continue
  if FUZZ_REPLAY=1 tests/fuzz/run.sh "$t" "$out" "${files[@]}"; then
    echo "fuzz $t: the ${#files[@]} inputs found before ran clean"
  else
    report "$t" " on the inputs found before" "$out/logs/$t-replay.log"
  fi
done
for t in command_parser scene checkpoint session repl; do
  if tests/fuzz/run.sh "$t" "$out" -max_total_time="$seconds"; then
    echo "fuzz $t: ok, $(grep -oE '^Done [0-9]+ runs in [0-9]+ second' "$out/logs/$t.log" | sed 's/^Done //;s/ second$/ s/')"
  else
    report "$t" "" "$out/logs/$t.log"
  fi
done
exit $failed
