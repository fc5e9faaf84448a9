#!/usr/bin/env bash
# Runs every catkin test (gtest and rostest) and the sanitizer builds' tests
# (scripts/sanitizer_tests.sh), then decides pass/fail from the result files:
# catkin's run_tests target exits 0 even when tests fail. Ends with one line "N passed, N failed".
set -uo pipefail
BUILD_DIR=${1:-build}
export PATH=/usr/bin:/bin:$PATH
# Debian's ROS profile scripts read unset variables: source them without nounset.
set +u
# shellcheck disable=SC1091
source "$(scripts/devel_dir.sh "$BUILD_DIR")/setup.bash"
set -u
export ROS_HOME=${ROS_HOME:-$(pwd)/$BUILD_DIR/ros_home}
export ROS_LOG_DIR=${ROS_LOG_DIR:-$ROS_HOME/log}
mkdir -p "$ROS_LOG_DIR"

rm -rf "$BUILD_DIR/test_results"
make --no-print-directory -C "$BUILD_DIR" run_tests -j1 2>&1 | tee "$BUILD_DIR/run_tests.log" \
  | grep -E '^\[ *(RUN|  *OK|  FAILED|  SKIPPED|  PASSED) |^\[ROSTEST\]|^ \* |FAILURE|Error' || true

# The sanitizer builds write their JUnit results under test_results/sanitizers, so the summary
# below counts them too. SANITIZERS=0 skips them.
if [[ "${SANITIZERS:-1}" != 0 ]]; then
  scripts/sanitizer_tests.sh "$BUILD_DIR" || echo "[sanitizers] FAILED (counted below)"
fi

# The failing test cases by name, next to the summary: CI keeps only the tail of this output.
/usr/bin/python3 - "$BUILD_DIR/test_results" <<'PY'
import pathlib, sys, xml.etree.ElementTree as ET
for path in sorted(pathlib.Path(sys.argv[1]).rglob("*.xml")):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as error:
        print(f"FAILED {path}: unreadable result file ({error})")
        continue
    for case in root.iter("testcase"):
        problem = next((child for child in case if child.tag in ("failure", "error")), None)
        if problem is not None:
            message = (problem.get("message") or problem.text or "").strip().splitlines()
            print(f"FAILED {path.name}: {case.get('classname')}.{case.get('name')}")
            for line in message[:8]:
                print(f"    {line[:300]}")
PY
summary=$(catkin_test_results --all "$BUILD_DIR/test_results" 2>&1 | tail -n 1)
echo "$summary"
# "Summary: 52 tests, 0 errors, 1 failures, 3 skipped"
read -r tests errors failures skipped < <(echo "$summary" |
  sed -E 's/.*Summary: ([0-9]+) tests, ([0-9]+) errors, ([0-9]+) failures, ([0-9]+) skipped.*/\1 \2 \3 \4/')
if ! [[ "$tests" =~ ^[0-9]+$ ]]; then
  echo "0 passed, 1 failed"
  echo "could not read the test summary: $summary" >&2
  exit 1
fi
failed=$((errors + failures))
passed=$((tests - failed - skipped))
if ((tests == 0)); then failed=1; echo "no test ran" >&2; fi
echo "$passed passed, $failed failed, $skipped skipped"
((failed == 0))
