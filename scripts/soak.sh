#!/usr/bin/env bash
# Soak test: the synthetic bag played in a loop at 3x rate (rosbag play -l -r 3 --clock, so every
# loop sets simulated time back) through launch/pipeline.launch, both nodelets in one manager, for
# SECONDS (default 120; the README documents a 1-hour run), while scripts/soak_monitor.py changes
# dynamic_reconfigure parameters of both nodelets at random, samples the manager's RSS from /proc
# and checks: no crash, RSS growth < SOAK_MAX_RSS_GROWTH_MB after the warm-up, every output matched
# to its input by stamp (none twice, none from nothing), at most SOAK_MAX_DROP_PERCENT lost within
# the drop policy. Prints one summary line.
#
#   scripts/soak.sh [SECONDS]          (make soak SOAK_SECONDS=3600 for the long run)
#
# Environment: BUILD_DIR (default build), SOAK_OUTPUT (default BUILD_DIR/soak), SOAK_RATE (3),
# SOAK_SCALE (synthetic image scale, 0.25), SOAK_FRAMES (bag frames, 40 = 4 s of bag),
# SOAK_SENSOR (radar), SOAK_WARMUP (s, 20), SOAK_MAX_RSS_GROWTH_MB (20), SOAK_MAX_DROP_PERCENT
# (15), SOAK_RECONFIGURE_PERIOD (mean s between parameter changes, 3), SOAK_PORT (master port).
set -euo pipefail

SECONDS_TO_RUN=${1:-120}
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${BUILD_DIR:-build}
[[ "$BUILD_DIR" = /* ]] || BUILD_DIR="$REPO/$BUILD_DIR"
OUT=${SOAK_OUTPUT:-$BUILD_DIR/soak}
RATE=${SOAK_RATE:-3}
SCALE=${SOAK_SCALE:-0.25}
FRAMES=${SOAK_FRAMES:-40}
SENSOR=${SOAK_SENSOR:-radar}
DEVEL=$("$REPO/scripts/devel_dir.sh" "$BUILD_DIR")
TOOLS="$DEVEL/lib/multimodal_nvs"
PY=/usr/bin/python3
export PATH=/usr/bin:/bin:$PATH

if ! [[ "$SECONDS_TO_RUN" =~ ^[0-9]+$ ]] || ((SECONDS_TO_RUN < 30)); then
  echo "soak: SECONDS must be an integer >= 30, got '$SECONDS_TO_RUN'" >&2
  exit 2
fi
for tool in make_synthetic_scene vod_to_bag; do
  [[ -x "$TOOLS/$tool" ]] || { echo "soak: $TOOLS/$tool is missing; build first" >&2; exit 1; }
done
[[ -f "$DEVEL/lib/libmultimodal_nvs_nodelets.so" ]] ||
  { echo "soak: the nodelets are not built in $BUILD_DIR" >&2; exit 1; }

"$PY" "$REPO/scripts/soak_monitor.py" --self-test
mkdir -p "$OUT"
BAG="$OUT/scene_${SCALE}_${FRAMES}.bag"
if [[ ! -f "$BAG" ]]; then
  echo "[soak] writing the synthetic bag ($FRAMES frames, scale $SCALE) to $BAG"
  rm -rf "$OUT/scene"
  "$TOOLS/make_synthetic_scene" --output "$OUT/scene" --scale "$SCALE" --num-frames "$FRAMES" \
    --threads 1 > "$OUT/scene.log" 2>&1
  "$TOOLS/vod_to_bag" --vod-root "$OUT/scene" --frames "0-$((FRAMES - 1))" --output "$BAG.tmp" \
    > "$OUT/bag.log" 2>&1
  mv "$BAG.tmp" "$BAG"
fi

# Debian's ROS profile scripts read unset variables: no nounset while sourcing.
set +u
# shellcheck disable=SC1091
source "$DEVEL/setup.bash"
set -u
PORT=${SOAK_PORT:-$("$PY" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')}
export ROS_MASTER_URI="http://127.0.0.1:$PORT" ROS_HOSTNAME=127.0.0.1
export ROS_HOME="$OUT/home" ROS_LOG_DIR="$OUT/log"
unset ROS_IP ROS_NAMESPACE
rm -rf "$ROS_LOG_DIR"
mkdir -p "$ROS_HOME" "$ROS_LOG_DIR"

PIDS=()
cleanup() {
  # Each background job was started by this script; SIGINT lets roslaunch stop its nodes.
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
    kill -INT "${PIDS[i]}" 2>/dev/null || true
  done
  for pid in "${PIDS[@]}"; do
    timeout 30 tail --pid="$pid" -f /dev/null 2>/dev/null || kill -KILL "$pid" 2>/dev/null || true
  done
}
trap cleanup EXIT

roscore -p "$PORT" > "$OUT/roscore.log" 2>&1 &
PIDS+=($!)
for _ in $(seq 100); do rosparam list > /dev/null 2>&1 && break; sleep 0.2; done
rosparam set /use_sim_time true

# Small render size: the soak is about endurance, not about the renderer's full-size cost.
roslaunch --wait multimodal_nvs pipeline.launch sensor:="$SENSOR" \
  params:="$REPO/config/demo_synthetic.yaml" render_height:=176 render_width:=320 \
  > "$OUT/pipeline.log" 2>&1 &
LAUNCH_PID=$!
PIDS+=($LAUNCH_PID)
# -l: the loop restarts simulated time (--clock) at every pass: the clock reset under test.
rosbag play -l -r "$RATE" --clock --quiet --delay=3 "$BAG" \
  --topics /camera/image_raw /camera/camera_info "/$SENSOR/points" /tf /tf_static \
  > "$OUT/play.log" 2>&1 &
PLAY_PID=$!
PIDS+=($PLAY_PID)

echo "[soak] ${SECONDS_TO_RUN} s: $BAG looped at ${RATE}x through pipeline.launch (master $ROS_MASTER_URI, logs in $OUT)"
set +e
"$PY" "$REPO/scripts/soak_monitor.py" --duration "$SECONDS_TO_RUN" \
  --warmup "${SOAK_WARMUP:-20}" --points "/$SENSOR/points" \
  --processes /multimodal_nvs_manager /depth_completion /conditioning_renderer \
  --reconfigure-period "${SOAK_RECONFIGURE_PERIOD:-3}" \
  --max-rss-growth-mb "${SOAK_MAX_RSS_GROWTH_MB:-20}" \
  --max-drop-percent "${SOAK_MAX_DROP_PERCENT:-15}" --json "$OUT/summary.json"
status=$?
set -e
# The monitor checks the nodes; roslaunch and the player must still be running too.
for pid in $LAUNCH_PID $PLAY_PID; do
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "soak: FAIL: process $pid (roslaunch or rosbag play) exited early; see $OUT/*.log" >&2
    status=1
  fi
done
if grep -q "process has died" "$OUT/pipeline.log"; then
  echo "soak: FAIL: roslaunch reports a dead process:" >&2
  grep "process has died" "$OUT/pipeline.log" >&2
  status=1
fi
exit "$status"
