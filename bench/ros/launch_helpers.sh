# Sourced by the node latency harnesses in bench/ros: a private ROS master on its own port, one
# launch file started in the background and stopped again. Callers cd to the repository root first.
set -eo pipefail  # no -u: catkin's setup scripts read unset variables
BUILD_DIR=${BUILD_DIR:-build}
export PATH=/usr/bin:/bin:$PATH
# shellcheck disable=SC1091
DEVEL=$(scripts/devel_dir.sh "$BUILD_DIR")
source "$DEVEL/setup.bash"
export ROS_HOME=${ROS_HOME:-$(pwd)/$BUILD_DIR/ros_home}
export ROS_LOG_DIR=${ROS_LOG_DIR:-$ROS_HOME/log}
mkdir -p "$ROS_LOG_DIR"
BENCH_PORT=${BENCH_ROS_PORT:-11411}
export ROS_MASTER_URI=http://localhost:$BENCH_PORT
BENCH_BIN=$DEVEL/lib/multimodal_nvs

# start_launch LOG_NAME LAUNCH_FILE ARGS...: roslaunch (with its master) in the background; waits
# for the node to come up.
start_launch() {
  local log=$1
  shift
  roslaunch -p "$BENCH_PORT" multimodal_nvs "$@" > "$ROS_LOG_DIR/$log.log" 2>&1 &
  BENCH_LAUNCH_PID=$!
  trap 'kill -INT $BENCH_LAUNCH_PID 2>/dev/null || true' EXIT
  sleep 3
}

stop_launch() {
  kill -INT "$BENCH_LAUNCH_PID"
  wait "$BENCH_LAUNCH_PID" || true
  trap - EXIT
}
