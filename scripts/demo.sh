#!/usr/bin/env bash
# make demo: the whole pipeline on the built-in synthetic street (or on real View-of-Delft data)
# with the tools and, through ROS, launch/demo.launch (both nodelets playing the bag), ending in
# demo_output/index.html.
#
#   scripts/demo.sh BUILD_DIR                       synthetic scene (scale 0.5, 16 frames)
#   DATA=/path/to/vod FRAMES=8350-8365 scripts/demo.sh BUILD_DIR    real VoD data
#
# Environment: DATA, FRAMES (A-B; default 8350-8365 with DATA), DEMO_OUTPUT (default
# <repo>/demo_output), DEMO_SCALE (synthetic image scale, 0.5), DEMO_SENSOR (radar|lidar, radar),
# DEMO_RETAIN (retention percent; default retain_percent of config/SENSOR.yaml), DEMO_GEN3C_SIZE
# ("H W" of the conditioning renders and the GEN3C export; default see below), DEMO_THREADS (0 = all cores), DEMO_ROS (0 skips the ROS
# stage), DEMO_ROS_RATE (bag playback rate, 1), DEMO_ROS_PORT (master port; default a free one),
# DEMO_RVIZ (0 skips the rviz screenshot).
#
# Stages run in the order of STAGES below; each is a function stage_<name> that prints one
# progress line and logs to demo_output/logs/<name>.log. To add a stage (e.g. playing the bag
# through the nodelets with roslaunch), write stage_<name> and insert <name> into STAGES.
set -euo pipefail

BUILD_DIR=${1:-build}
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO"
if [[ ! -d "$BUILD_DIR" ]]; then
  echo "demo: build directory '$BUILD_DIR' does not exist (run 'make demo' or 'make build')" >&2
  exit 2
fi
BUILD_DIR=$(cd "$BUILD_DIR" && pwd)
DEVEL=$("$REPO/scripts/devel_dir.sh" "$BUILD_DIR")
TOOLS="$DEVEL/lib/multimodal_nvs"
PY=/usr/bin/python3
OUT=${DEMO_OUTPUT:-$REPO/demo_output}
SCALE=${DEMO_SCALE:-0.5}
SENSOR=${DEMO_SENSOR:-radar}
RETAIN=${DEMO_RETAIN:-$("$REPO/scripts/config_value.sh" "$SENSOR" retain_percent)}
THREADS=${DEMO_THREADS:-0}

STAGES=(scene bag ros rviz depth render report)

# --- where the data comes from -------------------------------------------------------------
if [[ -n "${DATA:-}" ]]; then
  SOURCE="View-of-Delft data in $DATA"
  ROOT=$(cd "$DATA" && pwd)
  FRAMES=${FRAMES:-8350-8365}
else
  SOURCE="synthetic street (scale $SCALE, 16 frames)"
  ROOT="$OUT/scene"
  FRAMES=${FRAMES:-0-15}
fi
# Render size of the conditioning frames and of the GEN3C export (121 frames, GEN3C's layout).
# GEN3C's preprocessing scatters the depth map into the render grid, which leaves holes when the
# image is smaller than the render size, so the synthetic scene below scale 0.67 (968x608 at the
# default 0.5) renders at half GEN3C size, 352x640; VoD images (1936x1216) render at 704x1280.
if [[ -n "${DEMO_GEN3C_SIZE:-}" ]]; then
  read -r -a RENDER_SIZE <<< "$DEMO_GEN3C_SIZE"
elif [[ -z "${DATA:-}" ]] && awk -v s="$SCALE" 'BEGIN { exit !(s < 0.67) }'; then
  RENDER_SIZE=(352 640)
else
  RENDER_SIZE=(704 1280)
fi
if [[ ! "$FRAMES" =~ ^([0-9]+)-([0-9]+)$ ]]; then
  echo "demo: FRAMES must look like A-B (e.g. 8350-8365), got '$FRAMES'" >&2
  exit 2
fi
FIRST=$((10#${BASH_REMATCH[1]}))
LAST=$((10#${BASH_REMATCH[2]}))
FID=$(printf "%05d" "$FIRST")
BAG="$OUT/scene.bag"
ROS_OUT="$OUT/ros"
PIPELINE_BAG="$ROS_OUT/pipeline.bag"
DEPTH_PREFIX="$OUT/depth/$FID"
CONDITIONING="$OUT/conditioning"

# --- helpers -------------------------------------------------------------------------------
STAGE_NUMBER=0
TIMINGS="$OUT/logs/timings.tsv"
DEMO_START=$(date +%s.%N)

elapsed() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }

require_tool() {
  if [[ ! -x "$TOOLS/$1" ]]; then
    echo "demo: $TOOLS/$1 is missing; build first (make build BUILD_DIR=...)" >&2
    exit 1
  fi
}

# run_stage NAME: runs stage_NAME with its output in logs/NAME.log, prints one progress line.
run_stage() {
  local name=$1 log="$OUT/logs/$1.log" start status
  STAGE_NUMBER=$((STAGE_NUMBER + 1))
  start=$(date +%s.%N)
  printf "[demo %d/%d] %-8s %s\n" "$STAGE_NUMBER" "${#STAGES[@]}" "$name" "$(describe_"$name")"
  # A subshell with errexit of its own: any failing command ends the stage.
  set +e
  (set -e; "stage_$name") > "$log" 2>&1
  status=$?
  set -e
  if [[ $status == 0 ]]; then
    status=ok
  elif [[ $status == 3 ]]; then
    status=skipped
  else
    printf "[demo] stage '%s' failed (exit %s); last lines of %s:\n" "$name" "$status" "$log" >&2
    tr '\r' '\n' < "$log" | tail -n 15 >&2
    printf "%s\t%s\tfailed\n" "$name" "$(elapsed "$start")" >> "$TIMINGS"
    exit 1
  fi
  printf "%s\t%s\t%s\n" "$name" "$(elapsed "$start")" "$status" >> "$TIMINGS"
  printf "[demo %d/%d] %-8s %s in %s s\n" "$STAGE_NUMBER" "${#STAGES[@]}" "$name" "$status" \
    "$(elapsed "$start")"
}

# --- stages --------------------------------------------------------------------------------
describe_scene() {
  if [[ -n "${DATA:-}" ]]; then
    echo "using $SOURCE, frames $FRAMES"
  else
    echo "generating $SOURCE"
  fi
}
stage_scene() {
  if [[ -n "${DATA:-}" ]]; then
    for f in "$ROOT/lidar/training/image_2/$FID.jpg" "$ROOT/$SENSOR/training/velodyne/$FID.bin" \
             "$ROOT/$SENSOR/training/calib/$FID.txt"; do
      [[ -f "$f" ]] || { echo "missing $f (reference frame $FID, sensor $SENSOR)"; return 1; }
    done
    echo "using $ROOT"
    return 0
  fi
  require_tool make_synthetic_scene
  rm -rf "$ROOT"
  "$TOOLS/make_synthetic_scene" --output "$ROOT" --scale "$SCALE" --num-frames $((LAST - FIRST + 1)) \
    --first-frame "$FIRST" --threads "$THREADS"
}

describe_bag() { echo "converting frames $FRAMES to ${BAG#"$REPO"/}"; }
stage_bag() {
  require_tool vod_to_bag
  # Raw images: the conditioning renderer subscribes sensor_msgs/Image, and Debian has no
  # compressed image_transport plugin to decode /camera/image_raw/compressed for it.
  "$TOOLS/vod_to_bag" --vod-root "$ROOT" --frames "$FRAMES" --output "$BAG"
}

describe_ros() {
  if [[ "${DEMO_ROS:-1}" == 0 ]]; then
    echo "DEMO_ROS=0: skipped"
  else
    echo "roslaunch demo.launch (rosbag play --clock, both nodelets), rosbag record"
  fi
}
stage_ros() {
  [[ "${DEMO_ROS:-1}" != 0 ]] || return 3
  [[ -f "$DEVEL/lib/libmultimodal_nvs_nodelets.so" ]] ||
    { echo "the nodelets are not built in $BUILD_DIR"; return 1; }
  # Debian's ROS profile scripts read unset variables: no nounset while sourcing.
  set +u
  # shellcheck disable=SC1091
  source "$DEVEL/setup.bash"
  set -u
  # A master of our own on a free port (roslaunch starts it and stops it at the end), and ROS's
  # logs under demo_output.
  local port=${DEMO_ROS_PORT:-$("$PY" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')}
  export ROS_MASTER_URI="http://127.0.0.1:$port" ROS_HOSTNAME=127.0.0.1
  export ROS_HOME="$ROS_OUT/home" ROS_LOG_DIR="$ROS_OUT/log"
  unset ROS_IP ROS_NAMESPACE
  rm -rf "$ROS_OUT"
  mkdir -p "$ROS_HOME" "$ROS_LOG_DIR"
  local params="" rate=${DEMO_ROS_RATE:-1}
  [[ -n "${DATA:-}" ]] || params="$REPO/config/demo_synthetic.yaml"
  # The bag's duration at this rate, plus start-up, plus the tail: a hung launch cannot stall the
  # demo.
  local limit
  limit=$(awk -v n=$((LAST - FIRST + 1)) -v r="$rate" 'BEGIN { printf "%d", n / 10.0 / r + 90 }')
  echo "master $ROS_MASTER_URI, limit ${limit} s"
  timeout --signal=INT --kill-after=20 "$limit" roslaunch --port "$port" multimodal_nvs demo.launch \
    bag:="$BAG" gui:=false sensor:="$SENSOR" rate:="$rate" params:="$params" \
    render_height:="${RENDER_SIZE[0]}" render_width:="${RENDER_SIZE[1]}" \
    record:="$PIPELINE_BAG" wait:=true exit_at_end:=true delay:=3.0 linger:=3.0
  [[ -f "$PIPELINE_BAG" ]] || { echo "rosbag record wrote no $PIPELINE_BAG"; return 1; }
  "$PY" "$REPO/scripts/demo_ros_summary.py" --bag "$PIPELINE_BAG" --input-bag "$BAG" \
    --out "$ROS_OUT" --frames $((LAST - FIRST + 1)) --sensor "$SENSOR"
}

describe_rviz() {
  if [[ "${DEMO_ROS:-1}" == 0 || "${DEMO_RVIZ:-1}" == 0 ]]; then
    echo "DEMO_ROS=0 or DEMO_RVIZ=0: skipped"
  else
    echo "rviz under Xvfb (scripts/rviz_screenshot.sh): screenshot of depth and uncertainty"
  fi
}
stage_rviz() {
  [[ "${DEMO_ROS:-1}" != 0 && "${DEMO_RVIZ:-1}" != 0 ]] || return 3
  set +u
  # shellcheck disable=SC1091
  source "$DEVEL/setup.bash"
  set -u
  local params=""
  [[ -n "${DATA:-}" ]] || params="$REPO/config/demo_synthetic.yaml"
  mkdir -p "$ROS_OUT/rviz"
  # A blank panel or a failed rviz start is reported (here and in the report), not fatal: the rest
  # of the demo does not depend on it; make test's test_rviz_screenshot fails on it.
  "$REPO/scripts/rviz_screenshot.sh" "$BAG" "$ROS_OUT/rviz/rviz.png" sensor:="$SENSOR" \
    params:="$params" > "$ROS_OUT/rviz/shares.txt" 2>&1 ||
    echo "rviz_screenshot.sh failed (exit $?); see below"
  cat "$ROS_OUT/rviz/shares.txt"
}

# The sensor's model as the node runs it (config/SENSOR.yaml); DEMO_MODEL=local_gp_mle shows the
# reference-equivalent one.
DEPTH_MODEL=${DEMO_MODEL:-$("$REPO/scripts/config_value.sh" "$SENSOR" model)}
describe_depth() { echo "complete_depth ($DEPTH_MODEL) on frame $FID ($SENSOR, retain $RETAIN %)"; }
stage_depth() {
  require_tool complete_depth
  mkdir -p "$OUT/depth"
  "$TOOLS/complete_depth" --vod-root "$ROOT" --frame "$FIRST" --sensor "$SENSOR" \
    --model "$DEPTH_MODEL" --retain-percent "$RETAIN" --threads "$THREADS" \
    --output "$DEPTH_PREFIX" --png
}

describe_render() {
  if [[ -x "$TOOLS/render_conditioning" ]]; then
    echo "render_conditioning along frames $FRAMES," \
      "GEN3C export at ${RENDER_SIZE[0]}x${RENDER_SIZE[1]}"
  else
    echo "render_conditioning is not in this build: skipped"
  fi
}
stage_render() {
  [[ -x "$TOOLS/render_conditioning" ]] || return 3
  rm -rf "$CONDITIONING"
  "$TOOLS/render_conditioning" --image "$ROOT/lidar/training/image_2/$FID.jpg" \
    --depth "${DEPTH_PREFIX}_depth.npy" --valid "${DEPTH_PREFIX}_valid.npy" \
    --calib "$ROOT/$SENSOR/training/calib/$FID.txt" --vod-root "$ROOT" --frames "$FRAMES" \
    --size "${RENDER_SIZE[@]}" --gen3c --threads "$THREADS" --output "$CONDITIONING"
}

describe_report() { echo "metrics and ${OUT#"$REPO"/}/index.html"; }
stage_report() {
  local conditioning=""
  [[ -d "$CONDITIONING" ]] && conditioning="$CONDITIONING"
  "$PY" "$REPO/scripts/demo_report.py" --out "$OUT" --root "$ROOT" --frame "$FIRST" \
    --frames "$FRAMES" --sensor "$SENSOR" --depth-prefix "$DEPTH_PREFIX" \
    --conditioning "$conditioning" --timings "$TIMINGS" --bag "$BAG" \
    --ros-summary "$ROS_OUT/summary.json" --rviz "$ROS_OUT/rviz" \
    --title "multimodal_nvs demo: $SOURCE"
}

# --- run -----------------------------------------------------------------------------------
mkdir -p "$OUT/logs"
: > "$TIMINGS"
echo "[demo] $SOURCE -> ${OUT}"
for stage in "${STAGES[@]}"; do
  run_stage "$stage"
done
echo "[demo] done in $(elapsed "$DEMO_START") s"
grep -h '"metrics"' "$OUT/logs/report.log" | tail -n 1 || true
echo "[demo] report: $OUT/index.html"
