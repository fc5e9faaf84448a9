#!/usr/bin/env bash
# `make fuzz`: builds the libFuzzer harnesses of fuzz/ with clang (ASan + UBSan) into build_fuzz,
# writes their seed corpora and runs each harness for SECONDS (default 60). Exits non-zero when any
# harness finds a crash, a leak, a timeout or runs out of memory; the input is kept under
# build_fuzz/artifacts/<harness>/. One summary line per harness, then a final line.
#   scripts/fuzz.sh [SECONDS_PER_HARNESS]
# Environment: FUZZ_BUILD_DIR (build_fuzz), JOBS (2: build jobs, and harnesses run side by side),
# FUZZ_TIMEOUT per input in s (10), FUZZ_RSS_MB (2048), FUZZERS (space-separated subset of the
# harnesses), FUZZ_RUNS (stop each harness after this many inputs instead; SECONDS_PER_HARNESS stays
# its time limit, and a harness that stops on time short of FUZZ_RUNS fails), FUZZ_FORK (N:
# libFuzzer's fork mode, N processes).
set -uo pipefail
SECONDS_PER_HARNESS=${1:-60}
if ! [[ "$SECONDS_PER_HARNESS" =~ ^[0-9]+$ ]] || ((SECONDS_PER_HARNESS == 0)); then
  echo "usage: scripts/fuzz.sh [SECONDS_PER_HARNESS > 0]" >&2
  exit 2
fi
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
export PATH=/usr/bin:/bin:$PATH
BUILD=${FUZZ_BUILD_DIR:-build_fuzz}
JOBS=${JOBS:-2}
TIMEOUT=${FUZZ_TIMEOUT:-10}
RSS_MB=${FUZZ_RSS_MB:-2048}
RUNS=${FUZZ_RUNS:-}
FORK=${FUZZ_FORK:-}
if [[ -n "$FORK" ]] && ! [[ "$FORK" =~ ^[1-9][0-9]*$ ]]; then
  echo "scripts/fuzz.sh: FUZZ_FORK must be a positive whole number" >&2
  exit 2
fi
if [[ -n "$RUNS" ]] && ! [[ "$RUNS" =~ ^[1-9][0-9]*$ ]]; then
  echo "scripts/fuzz.sh: FUZZ_RUNS must be a positive whole number" >&2
  exit 2
fi
ALL_FUZZERS="fuzz_cloud fuzz_image fuzz_kitti_calib fuzz_camera_info fuzz_vod_pose fuzz_bin fuzz_pcd fuzz_npy"
read -r -a fuzzers <<<"${FUZZERS:-$ALL_FUZZERS}"

mkdir -p "$BUILD"
# A build directory inside the package: catkin's tools (catkin_lint, a workspace's package search)
# must not read it as sources.
touch "$BUILD/CATKIN_IGNORE"
echo "[fuzz] building the harnesses into $BUILD (clang, ASan + UBSan, $JOBS jobs)"
if ! cmake -S fuzz -B "$BUILD" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  >"$BUILD/configure.log" 2>&1; then
  cat "$BUILD/configure.log"
  exit 1
fi
if ! cmake --build "$BUILD" -j "$JOBS" >"$BUILD/build.log" 2>&1; then
  grep -E 'error|Error' "$BUILD/build.log" | head -n 40
  exit 1
fi

# Fresh seeds every run (they are code); the working corpus under $BUILD/corpus persists, so
# repeated runs start where the last one stopped.
rm -rf "$BUILD/seeds"
"$BUILD/write_fuzz_seeds" "$BUILD/seeds" || exit 1

# Leaks fail the run (libFuzzer checks after every input that allocated more than it freed).
# UBSan aborts on the first report (the code is also built with -fno-sanitize-recover).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:symbolize=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

# A figure from libFuzzer's -print_final_stats block ("stat::peak_rss_mb: 531").
final_stat() { sed -nE "s/^stat::$1: *([0-9]+).*/\1/p" "$2" | tail -n 1; }

# run_harness FUZZER: runs one harness and writes its summary line to $BUILD/logs/FUZZER.result;
# exits non-zero when it failed.
run_harness() {
  local fuzzer=$1
  local corpus="$BUILD/corpus/$fuzzer"
  local artifacts="$BUILD/artifacts/$fuzzer"
  local log="$BUILD/logs/$fuzzer.log"
  local result="$BUILD/logs/$fuzzer.result"
  mkdir -p "$corpus" "$artifacts" "$BUILD/logs"
  local dict=()
  [[ -f "fuzz/$fuzzer.dict" ]] && dict=("-dict=fuzz/$fuzzer.dict")
  local runs=()
  [[ -n "$RUNS" ]] && runs=("-runs=$RUNS")
  local started=$SECONDS
  # -purge_allocator_interval=30: once RSS passes half the limit, libFuzzer purges ASan's allocator
  # every second by default (madvise), and the next inputs fault every page back in; on this VM
  # (~30 us per page fault) that took fuzz_camera_info (yaml-cpp: many small nodes per input) from
  # ~4.5 k to ~320 inputs/s within ten minutes. Never purging let its RSS climb towards the limit.
  # FUZZ_FORK=N: libFuzzer's fork mode, N child processes on the shared corpus, each restarted after
  # a short job (so allocator state starts fresh); findings of any kind stop the run as without it.
  local fork=()
  [[ -n "$FORK" ]] && fork=("-fork=$FORK" -ignore_crashes=0 -ignore_ooms=0 -ignore_timeouts=0)
  "$BUILD/$fuzzer" -max_total_time="$SECONDS_PER_HARNESS" -timeout="$TIMEOUT" \
    -rss_limit_mb="$RSS_MB" -purge_allocator_interval=30 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" "${dict[@]}" "${runs[@]}" "${fork[@]}" "$corpus" \
    "$BUILD/seeds/$fuzzer" >"$log" 2>&1
  local rc=$?
  local elapsed=$((SECONDS - started))
  local execs rate rss status cov ft corp figures
  execs=$(final_stat number_of_executed_units "$log")
  rate=$(final_stat average_exec_per_sec "$log")
  rss=$(final_stat peak_rss_mb "$log")
  # The last status line, e.g. "#123456 DONE cov: 412 ft: 1830 corp: 97/21Kb ..." (fork mode:
  # "#123456: cov: 2071 ft: 1835 corp: 221 exec/s 3467 oom/timeout/crash: 0/0/0 ...", and the
  # parent prints no final stats: the executions are the status line's count).
  status=$(grep -E '^#[0-9]+' "$log" | tail -n 1)
  if [[ -n "$FORK" ]]; then
    execs=$(sed -nE 's/^#([0-9]+):.*/\1/p' <<<"$status")
    rate=$((${execs:-0} / (elapsed > 0 ? elapsed : 1)))
  fi
  cov=$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<<"$status")
  ft=$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<<"$status")
  corp=$(sed -nE 's/.* corp: ([0-9]+).*/\1/p' <<<"$status")
  figures="${execs:-?} execs in ${elapsed} s (${rate:-?}/s), cov ${cov:-?}, ft ${ft:-?}, corpus ${corp:-?}, peak RSS ${rss:-?} MB"
  if ((rc == 0)) && [[ -n "$RUNS" ]] && ((${execs:-0} < RUNS)); then
    echo "[fuzz] $fuzzer: FAILED (time limit before $RUNS runs), $figures; log: $log" >"$result"
    return 1
  fi
  if ((rc == 0)); then
    echo "[fuzz] $fuzzer: ok, $figures" >"$result"
    return 0
  fi
  local kind=crash artifact
  grep -q 'ERROR: LeakSanitizer' "$log" && kind=leak
  grep -q 'ERROR: libFuzzer: timeout' "$log" && kind=timeout
  grep -q 'ERROR: libFuzzer: out-of-memory' "$log" && kind=out-of-memory
  artifact=$(sed -nE 's/.*Test unit written to (.*)$/\1/p' "$log" | tail -n 1)
  {
    echo "[fuzz] $fuzzer: FAILED ($kind, exit $rc), $figures; input: ${artifact:-none}; log: $log"
    grep -E 'ERROR:|runtime error:|invariant violated|SUMMARY:' "$log" | head -n 5 | sed 's/^/    /'
  } >"$result"
  return 1
}

# Each harness is one process on one core (fork mode: FORK children), so JOBS of them run side by
# side: CI's 8 harnesses x 30 s took 4 minutes one after the other on its 2 cores. Every harness
# still gets its full time on a core of its own; the results are printed in the harnesses' order.
parallel=$JOBS
[[ -n "$FORK" ]] && parallel=1
for fuzzer in "${fuzzers[@]}"; do
  rm -f "$BUILD/logs/$fuzzer.result"
  while (($(jobs -pr | wc -l) >= parallel)); do wait -n; done
  run_harness "$fuzzer" &
done
wait
# The verdicts are the result files' (a harness that left none failed).
failed=0
for fuzzer in "${fuzzers[@]}"; do
  result="$BUILD/logs/$fuzzer.result"
  if [[ -f "$result" ]]; then
    cat "$result"
    grep -q "^\[fuzz\] $fuzzer: ok" "$result" || failed=$((failed + 1))
  else
    echo "[fuzz] $fuzzer: FAILED (no result; log: $BUILD/logs/$fuzzer.log)"
    failed=$((failed + 1))
  fi
done

budget="${SECONDS_PER_HARNESS} s"
[[ -n "$RUNS" ]] && budget="$RUNS runs (at most ${SECONDS_PER_HARNESS} s)"
echo "fuzz: ${#fuzzers[@]} harnesses x ${budget}, $((${#fuzzers[@]} - failed)) ok, $failed failed"
((failed == 0))
