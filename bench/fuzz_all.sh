#!/usr/bin/env bash
# Fuzz every target of tests/fuzz for RUNS inputs each (default 1,000,000), one after the other on
# one core, under AddressSanitizer and UBSan (build-asan/, built as scripts/fuzz.sh builds it, on
# the corpora earlier runs left there). Prints a table and appends it to bench/results/fuzz.csv:
# target, inputs run, seconds, exec/s, corpus size, new units, peak RSS, result (ok, or crash,
# leak, timeout, oom with the input saved in build-asan/artifacts/).
# Usage: bench/fuzz_all.sh [RUNS [TARGET...]]; FUZZ_MAX_SECONDS=S stops each target after S seconds
# if it has not run its RUNS inputs by then (the row then says how many it ran). FUZZ_WORKERS=W
# runs W processes of each target at once on its corpus (which they share as libFuzzer reloads
# it), each with its own seed and RUNS/W inputs; the row gives their sum.
set -uo pipefail
cd "$(dirname "$0")/.."
runs=${1:-1000000}
shift $(($# > 0 ? 1 : 0))
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(command_parser scene checkpoint session repl)
out=build-asan
csv=bench/results/fuzz.csv
tests/fuzz/build.sh "$out" || exit 1
[ -f "$csv" ] || echo "date,target,inputs,seconds,exec_per_s,corpus_files,corpus_kb,new_units,peak_rss_mb,result" > "$csv"
workers=${FUZZ_WORKERS:-1}
# A libFuzzer final statistic, summed over the workers' logs (the largest for peak_rss_mb).
stat() {
  local total=0 v
  for l in "${logs[@]}"; do
    v=$(grep -oE "stat::$1: *[0-9]+" "$l" | grep -oE '[0-9]+$' || echo 0)
    if [ "$1" = peak_rss_mb ]; then total=$((v > total ? v : total)); else total=$((total + v)); fi
  done
  echo $total
}
printf '%-15s %10s %8s %8s %14s  %s\n' target inputs seconds exec/s corpus result
failed=0
for t in "${targets[@]}"; do
  start=$(date +%s.%N)
  limit=()
  [ -z "${FUZZ_MAX_SECONDS:-}" ] || limit=(-max_total_time="$FUZZ_MAX_SECONDS")
  logs=()
  if [ "$workers" -le 1 ]; then
    tests/fuzz/run.sh "$t" "$out" -runs="$runs" "${limit[@]}"
    status=$?
    logs=("$out/logs/$t.log")
  else
    pids=()
    for w in $(seq 1 "$workers"); do
      FUZZ_WORKER=$w tests/fuzz/run.sh "$t" "$out" -runs=$(((runs + workers - 1) / workers)) -seed="$w" "${limit[@]}" &
      pids+=($!)
      logs+=("$out/logs/$t-$w.log")
    done
    status=0
    for p in "${pids[@]}"; do wait "$p" || status=1; done
  fi
  seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  inputs=$(stat number_of_executed_units)
  result=ok
  if [ $status -ne 0 ]; then
    failed=1
    if grep -q 'ERROR: libFuzzer: timeout' "${logs[@]}"; then result=timeout
    elif grep -q 'out-of-memory' "${logs[@]}"; then result=oom
    elif grep -q 'ERROR: LeakSanitizer' "${logs[@]}"; then result=leak
    else result=crash; fi
    # The failing input (libFuzzer also writes slow units, which are not failures).
    artifact=$(cat "${logs[@]}" | grep -oE 'Test unit written to [^ ]+-(crash|leak|timeout|oom)-[^ ]+' | tail -n 1 |
      sed 's/.* //' || true)
    [ -z "$artifact" ] || result="$result $artifact"
  fi
  files=$(find "$out/corpus/$t" -type f | wc -l)
  kb=$(du -sk "$out/corpus/$t" | cut -f1)
  rate=$(awk -v n="$inputs" -v s="$seconds" 'BEGIN { printf "%.0f", (s > 0 ? n / s : 0) }')
  printf '%-15s %10s %8s %8s %8s files  %s\n' "$t" "$inputs" "$seconds" "$rate" "$files" "$result"
  echo "$(date -u +%Y-%m-%dT%H:%M:%SZ),$t,$inputs,$seconds,$rate,$files,$kb,$(stat new_units_added),$(stat peak_rss_mb),$result" >> "$csv"
done
exit $failed
