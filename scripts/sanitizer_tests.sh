#!/usr/bin/env bash
# Sanitizer builds of `make test`. Usage: scripts/sanitizer_tests.sh [BUILD_DIR]
#
#   asan  BUILD_DIR/asan: test_core and test_tools (core, I/O, the tools run as processes) under
#         AddressSanitizer + LeakSanitizer + UndefinedBehaviorSanitizer, -fno-sanitize-recover=all.
#   tsan  BUILD_DIR/tsan: the nodelet rostests (depth completion: scene, raw and compressed, and
#         bad input; conditioning renderer) under ThreadSanitizer, nodes run standalone.
#
# Each sanitizer build is a second catkin configure of this package with its own compiler flags,
# and builds only what its tests need. Results go to BUILD_DIR/test_results/sanitizers as JUnit XML
# (the test binaries' own, plus one file per build with a "build" and a "no sanitizer report" case),
# so that scripts/run_tests.sh counts them with the rest. SANITIZERS="asan" or "tsan" selects one.
# Exits non-zero when any build, test or sanitizer report fails.
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
JOBS=${JOBS:-2}
SELECTED=${SANITIZERS:-asan tsan}
[[ "$SELECTED" == 1 || "$SELECTED" == all ]] && SELECTED="asan tsan"
RESULTS=$BUILD_DIR/test_results/sanitizers
export PATH=/usr/bin:/bin:$PATH
mkdir -p "$RESULTS"
RESULTS=$(cd "$RESULTS" && pwd)
SUPPRESSIONS=$(pwd)/test/tsan.supp
# shellcheck source=devel_dir.sh
source scripts/devel_dir.sh

failures=0
summary=()

# One JUnit file per sanitizer build: testcase NAME passes, or fails with MESSAGE and the file
# DETAILS (build log tail or sanitizer reports).
junit_begin() { JUNIT_CASES=""; JUNIT_TESTS=0; JUNIT_FAILURES=0; }
junit_case() {  # name, ok (0/1), message, details file
  local name=$1 ok=$2 message=${3:-} details=${4:-}
  JUNIT_TESTS=$((JUNIT_TESTS + 1))
  if ((ok)); then
    JUNIT_CASES+="  <testcase classname=\"sanitizers\" name=\"$name\" time=\"0\"/>"$'\n'
  else
    JUNIT_FAILURES=$((JUNIT_FAILURES + 1))
    local text=""
    [[ -n "$details" && -f "$details" ]] && text=$(tail -c 20000 "$details" |
      sed -e 's/&/\&amp;/g' -e 's/</\&lt;/g' -e 's/>/\&gt;/g')
    JUNIT_CASES+="  <testcase classname=\"sanitizers\" name=\"$name\" time=\"0\"><failure"
    JUNIT_CASES+=" message=\"$message\">$text</failure></testcase>"$'\n'
  fi
}
junit_write() {  # suite name, file
  {
    echo '<?xml version="1.0" encoding="UTF-8"?>'
    echo "<testsuite name=\"$1\" tests=\"$JUNIT_TESTS\" failures=\"$JUNIT_FAILURES\" errors=\"0\">"
    printf '%s' "$JUNIT_CASES"
    echo '</testsuite>'
  } > "$2"
}

# configure NAME CXX_FLAGS: a catkin configure into BUILD_DIR/NAME with the sanitizer's flags.
# Below BUILD_DIR, so that rosrun (which skips <package>/build/) never finds their executables.
# RelWithDebInfo without -DNDEBUG: -O1 (what the sanitizers' own documentation suggests) with
# -g1 (line tables, no variable info): reports keep file:line, Eigen's and libstdc++'s bounds
# assertions stay on. Measured on test_ground_gp.cpp under ASan: -O2 -g 29.4 s, -O1 -g1 11.2 s;
# the sanitizer builds were more than half of CI's `make test`.
configure() {
  local dir=${BUILD_DIR}/$1 flags=$2
  cmake -S . -B "$dir" -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
    -DCATKIN_DEVEL_PREFIX="$(devel_dir "$dir")" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags"
}

# build NAME LOG TARGETS...: configure and build; true on success.
build() {
  local name=$1 log=$2 flags
  shift 2
  case $name in
    asan) flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
          flags+=" -D_GLIBCXX_ASSERTIONS" ;;
    tsan) flags="-fsanitize=thread" ;;
  esac
  { configure "$name" "$flags" && make --no-print-directory -C "${BUILD_DIR}/$name" -j"$JOBS" "$@"; } \
    > "$log" 2>&1
}

# build_or_record_failure NAME LABEL TARGETS...: build(); on failure the build is the JUnit
# file's only (failed) case, the summary says so, and the log's tail is shown. True on success.
build_or_record_failure() {
  local name=$1 label=$2 log=$RESULTS/$1_build.log
  shift 2
  if build "$name" "$log" "$@"; then
    junit_case build 1
    return 0
  fi
  junit_case build 0 "sanitizer build failed" "$log"
  junit_write "$name" "$RESULTS/sanitizer-$name.xml"
  summary+=("$label: BUILD FAILED (see $log)")
  failures=$((failures + 1))
  tail -n 30 "$log"
  return 1
}

# Sanitizer reports, one file per process (log_path), so that findings in child processes (the
# tools test_core runs, the nodes rostest starts) count even when their test only checks output.
reports_clean() {  # report directory, combined output file
  local dir=$1 out=$2
  : > "$out"
  for f in "$dir"/*; do [[ -f "$f" ]] && { echo "=== $f"; cat "$f"; } >> "$out"; done
  [[ ! -s "$out" ]]
}

minutes() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }

run_asan() {
  local dir=${BUILD_DIR}/asan reports=$RESULTS/asan_reports
  local start=$SECONDS
  junit_begin
  echo "[sanitizers] asan+ubsan: building test_core, test_tools and the tools they run into $dir"
  build_or_record_failure asan "asan+ubsan" test_core test_tools complete_depth evaluate_depth \
    render_conditioning make_synthetic_scene || return
  local built=$SECONDS
  rm -rf "$reports" && mkdir -p "$reports"
  # halt_on_error with -fno-sanitize-recover=all: the first finding ends the process.
  # detect_leaks: LeakSanitizer (the default on x86_64 Linux, spelled out).
  export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1"
  ASAN_OPTIONS+=":check_initialization_order=1:strict_init_order=1:log_path=$reports/asan"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:log_path=$reports/ubsan"
  # Parity: only the radar reference cases. 00549_lidar_local_gp_mle_s16 alone takes more than
  # 4 minutes under ASan (large neighbour sets; a few seconds in Release) and exercises no code the
  # radar cases do not; the normal build runs all of them.
  export MMNVS_PARITY_CASES='.*_radar_.*'
  # The two binaries run side by side on the 2 cores (each is mostly one thread under ASan): their
  # run took 135 s instead of 55 + 110 s one after the other. Each has its own TEST_TMPDIR (gtest's
  # TempDir()), so that their scratch files never meet.
  local rc=0 out binary binary_rc
  declare -A pids
  for binary in test_core test_tools; do
    mkdir -p "$dir/tmp_$binary"
    TEST_TMPDIR=$(realpath -m "$dir/tmp_$binary")/ "$(devel_dir "$dir")/lib/multimodal_nvs/$binary" \
      --gtest_output="xml:$RESULTS/asan-gtest-$binary.xml" > "$RESULTS/asan_$binary.log" 2>&1 &
    pids[$binary]=$!
  done
  for binary in test_core test_tools; do
    out=$RESULTS/asan_$binary.log
    wait "${pids[$binary]}"
    binary_rc=$?
    grep -E '^\[  FAILED  \]|^\[  PASSED  \]' "$out" | sort -u
    junit_case "${binary}_exit_status" $((binary_rc == 0)) "$binary exited with $binary_rc" "$out"
    if ((binary_rc != 0)); then rc=$binary_rc; tail -n 30 "$out"; fi
  done
  unset ASAN_OPTIONS UBSAN_OPTIONS MMNVS_PARITY_CASES
  local clean=1
  reports_clean "$reports" "$RESULTS/asan_reports.txt" || clean=0
  junit_case no_asan_ubsan_reports "$clean" "sanitizer reports" "$RESULTS/asan_reports.txt"
  junit_write asan "$RESULTS/sanitizer-asan.xml"
  local verdict=ok
  if ((rc != 0 || !clean)); then
    verdict=FAILED
    failures=$((failures + 1))
    ((clean)) || head -n 60 "$RESULTS/asan_reports.txt"
  fi
  summary+=("asan+ubsan: $verdict (tests exit $rc, reports: $((1 - clean)); build $(minutes $((built - start))), run $(minutes $((SECONDS - built))))")
}

run_tsan() {
  local dir=${BUILD_DIR}/tsan reports=$RESULTS/tsan_reports
  local start=$SECONDS
  junit_begin
  echo "[sanitizers] tsan: building the nodelets, nodes and rostest gtests into $dir"
  build_or_record_failure tsan tsan multimodal_nvs_nodelets depth_completion_node \
    conditioning_renderer_node scene_publisher test_depth_scene test_depth_bad_input test_renderer ||
    return
  local built=$SECONDS
  rm -rf "$reports" && mkdir -p "$reports"
  # A subshell: the TSan workspace's setup.bash must not leak into the caller's environment.
  (
    set +u
    # shellcheck disable=SC1091
    source "$(devel_dir "$dir")/setup.bash"
    set -u
    export ROS_HOME=$(pwd)/$dir/ros_home
    export ROS_LOG_DIR=$ROS_HOME/log
    mkdir -p "$ROS_LOG_DIR"
    # ignore_noninstrumented_modules: Debian's roscpp, nodelet, class_loader and Boost are not
    # built with -fsanitize=thread, so TSan sees none of their memory accesses or atomics; this
    # makes it also ignore what their calls into libc (memcpy, free, mutexes) touch, and drop the
    # reports raised inside those calls (lock-order inversions among roscpp's own mutexes, races
    # on memory roscpp hands between threads through uninstrumented shared_ptr atomics).
    # Synchronisation they do through pthread is still seen, and every access our instrumented code
    # makes is still checked. Standalone nodes only: the nodelet manager is Debian's uninstrumented
    # /usr/lib/nodelet/nodelet; depth_completion_node hosts the same nodelet class through the same
    # nodelet::Loader and worker threads.
    export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:ignore_noninstrumented_modules=1"
    TSAN_OPTIONS+=":suppressions=$SUPPRESSIONS:log_path=$reports/tsan"
    status=0
    for run in "depth_scene.test mode:=standalone" "depth_scene.test mode:=standalone compressed:=true" \
      "depth_bad_input.test mode:=standalone" "renderer.test mode:=standalone"; do
      read -r file args <<< "$run"
      name=tsan-${file%.test}-$(echo "$args" | sed -E 's/[ :=]+/_/g')
      echo "[sanitizers] tsan: rostest $run"
      rostest --results-base-dir "$RESULTS" --results-filename "$name.xml" multimodal_nvs \
        $file $args > "$RESULTS/$name.log" 2>&1 || status=1
      grep -E 'RESULT:|TESTS:|FAILURES:|ERRORS:' "$RESULTS/$name.log" | sed 's/^/    /'
    done
    exit $status
  )
  local rc=$?
  local clean=1
  reports_clean "$reports" "$RESULTS/tsan_reports.txt" || clean=0
  junit_case rostests_exit_status $((rc == 0)) "a TSan rostest failed" "$RESULTS/tsan_reports.txt"
  junit_case no_tsan_reports "$clean" "ThreadSanitizer reports" "$RESULTS/tsan_reports.txt"
  junit_write tsan "$RESULTS/sanitizer-tsan.xml"
  local verdict=ok
  if ((rc != 0 || !clean)); then
    verdict=FAILED
    failures=$((failures + 1))
    ((clean)) || head -n 80 "$RESULTS/tsan_reports.txt"
  fi
  summary+=("tsan: $verdict (rostests exit $rc, reports: $((1 - clean)); build $(minutes $((built - start))), run $(minutes $((SECONDS - built))))")
}

total_start=$SECONDS
for s in $SELECTED; do
  case $s in
    asan) run_asan ;;
    tsan) run_tsan ;;
    *) echo "unknown sanitizer '$s' (asan, tsan)" >&2; failures=$((failures + 1)) ;;
  esac
done
echo "[sanitizers] summary ($(minutes $((SECONDS - total_start))) in all; results in $RESULTS):"
for line in "${summary[@]}"; do echo "  $line"; done
((failures == 0))
