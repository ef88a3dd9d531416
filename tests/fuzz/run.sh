#!/usr/bin/env bash
# Runs one fuzz target of BUILD_DIR on its corpus (BUILD_DIR/corpus/TARGET, seeded by seeds.sh)
# with its options, the rest of the arguments passed to libFuzzer (-max_total_time=20,
# -runs=1000000). The log goes to BUILD_DIR/logs/TARGET.log, a failing input to
# BUILD_DIR/artifacts/. Exit status: libFuzzer's, or 1 when the log holds a sanitizer report.
# With FUZZ_WORKER=K set (one of several processes on the same corpus), the log is TARGET-K.log;
# with FUZZ_REPLAY set, TARGET-replay.log.
# Usage: tests/fuzz/run.sh TARGET BUILD_DIR [LIBFUZZER_FLAG...]; FUZZ_REPLAY=1 tests/fuzz/run.sh
# TARGET BUILD_DIR FILE...
set -uo pipefail
cd "$(dirname "$0")/../.."
target=$1
build=$(realpath "$2")
shift 2
corpus=$build/corpus
# Limits: a hang, or memory beyond these (2 GB in all, 1 GB in one allocation), is a bug.
options=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1)
asan_extra=
max_len=  # libFuzzer's longest input, when the target sets one
case $target in
  command_parser) max_len=256; options+=(-timeout=5) ;;
  scene) max_len=4096; options+=(-dict="$corpus/scene.dict" -timeout=20) ;;
  checkpoint) options+=(-timeout=10) ;;  # -max_len: the largest seed
  # Sessions run some hundred inputs a second: the entropic schedule's bookkeeping of every
  # coverage feature, a quarter of each run's time here, is left out (-entropic=0).
  # AddressSanitizer keeps freed blocks in a quarantine (256 MB by default) to catch their use,
  # and a size class keeps the memory it once held: the session targets allocate and free blocks
  # of 80 to 128 KiB by the thousand (zlib's buffers, four for each PNG frame written, and the
  # frames' pixels: 4,100 to 41,600 per size class over the terminal corpus), and each of those
  # classes came to hold a whole quarantine (about 280 MB each). Replaying the terminal corpus
  # (6,471 inputs) ended at 485, 1,138, 1,721 and 2,567 MB resident with quarantines of 16, 64,
  # 128 and 256 MB, 38 MB of it live (an out-of-memory at 256). 32 MB is still ten inputs' frees
  # (2.9 MB an input on average): a use after free within an input is still caught unless more than
  # 32 MB is freed in between.
  session | repl)
    max_len=2048
    options+=(-dict="$corpus/session.dict" -timeout=30 -entropic=0)
    asan_extra=:quarantine_size_mb=32
    ;;
  *)
    echo "run.sh: no target $target" >&2
    exit 2
    ;;
esac
# With FUZZ_REPLAY set, no fuzzing: the arguments are files, run once each in that order in one
# process (what an input leaves behind, readline's history or kill ring, reaches the next), whole
# (no -max_len).
inputs=("$corpus/$target")
if [ -n "${FUZZ_REPLAY:-}" ]; then
  [ $# -gt 0 ] || { echo "run.sh: FUZZ_REPLAY and no files" >&2; exit 2; }
  inputs=()
elif [ -n "$max_len" ]; then
  options+=(-max_len="$max_len")
fi
mkdir -p "$build/logs" "$build/artifacts"
log=$build/logs/$target${FUZZ_WORKER:+-$FUZZ_WORKER}${FUZZ_REPLAY:+-replay}.log
ASAN_OPTIONS=detect_leaks=1${asan_extra:-} UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp \
  "$build/tests/fuzz/${target}_fuzz" "${options[@]}" -artifact_prefix="$build/artifacts/$target-" "$@" \
  "${inputs[@]}" > "$log" 2>&1
status=$?
if [ $status -eq 0 ] && grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:|silt fuzz:' "$log"; then
  status=1
fi
exit $status
