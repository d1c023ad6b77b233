#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/; in the sanitizer build, build-asan/: clang + ASan + UBSan) and runs
# each for a bounded time from its corpus: tests/fuzz/<target>/ (inputs that once failed) and the bundled
# presets as seeds. A crash, a sanitizer report, an input slower than 20 s or an allocation over 2 GB fails
# the run and leaves the input in build-asan/findings/<target>/: fix the cause, then copy the input into
# tests/fuzz/<target>/ so ctest replays it in every build (fuzz_replay.<target>).
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 45; docs/design/reliability.md has the long run)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-45}"
cmake --preset asan >/dev/null
cmake --build --preset fuzz
# One target per core at a time: each still gets a whole core for SECONDS (nine targets on two cores: five
# rounds of SECONDS instead of nine).
fuzz_one() {
  local target=$1 corpora=$2
  local work=build-asan/corpus/$target        # new inputs go to the first folder; the seeds stay untouched
  local findings=build-asan/findings/$target
  mkdir -p "$work" "$findings"
  # shellcheck disable=SC2086  # corpora is a list of folders
  if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
       LSAN_OPTIONS=suppressions=fuzz/lsan.supp \
       "build-asan/bin/$target" "$work" $corpora -max_total_time="$seconds" -timeout=20 \
       -rss_limit_mb=2048 -malloc_limit_mb=2048 -max_len=65536 -artifact_prefix="$findings/" \
       -print_final_stats=1 > "build-asan/$target.log" 2>&1; then
    echo "FAILED: $target; the input is in $findings/, the report in build-asan/$target.log:"
    grep -v "^#\|^INFO\|^replay" "build-asan/$target.log" | tail -40
    return 1
  fi
  echo "$target: $(grep -E "stat::number_of_executed_units" "build-asan/$target.log" | tail -1)"
}
status=0
running=0
while read -r target corpora; do
  [ -n "$target" ] || continue
  if [ "$running" -ge "$(nproc)" ]; then
    wait -n || status=1
    running=$((running - 1))
  fi
  echo "fuzzing $target for ${seconds} s"
  fuzz_one "$target" "$corpora" &
  running=$((running + 1))
done < build-asan/fuzz-targets.txt
while [ "$running" -gt 0 ]; do
  wait -n || status=1
  running=$((running - 1))
done
exit $status
