#!/usr/bin/env bash
# make eval: the paper's depth and novel-view tables, with the baselines side by side, on the
# View-of-Delft frames in the shared data directory and on the built-in synthetic street.
# Writes eval_output/tables.md + tables.json (and every raw JSON under eval_output/raw/) and prints
# the tables.
#
#   scripts/eval.sh BUILD_DIR
#
# Environment: MMNVS_DATA_DIR (default <repo>/../shared/data), EVAL_OUTPUT (default
# <repo>/eval_output), EVAL_THREADS (0 = all cores), EVAL_SKIP ("vod", "synthetic", "nvs" or a
# space-separated combination), EVAL_KEEP_FRAMES=1 keeps the rendered frames of the NVS table,
# EVAL_REGENERATE=1 rebuilds the cached synthetic scene.
#
# Suites and tables (per suite):
#   1 radar input, every model, all pixels and kept 80%          (full resolution, stride 1)
#   2 LiDAR input: 1-in-4 returns as input, the rest as ground truth (stride 4)
#   3 radius ablation r = 1, 2, 4 deg (local_gp_mle) and retention ablation 40/60/80/100 %
#   4 novel view: depth from local_gp_mle, kernel, nearest, constant on radar at 40/60/80/100 %,
#     rendered into the recorded trajectory with render_conditioning (PSNR/SSIM, covered PSNR,
#     coverage); the recorded poses only (16 frames), which gives the same metrics as rendering
#     GEN3C's 121 frames, whose frames 0, 8, ..., 120 are the recorded poses.
set -euo pipefail

BUILD_DIR=${1:-build}
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO"
if [[ ! -d "$BUILD_DIR" ]]; then
  echo "eval: build directory '$BUILD_DIR' does not exist (run 'make eval' or 'make build')" >&2
  exit 2
fi
BUILD_DIR=$(cd "$BUILD_DIR" && pwd)
TOOLS="$BUILD_DIR/devel/lib/multimodal_nvs"
PY=/usr/bin/python3
DATA=${MMNVS_DATA_DIR:-$REPO/../shared/data}
OUT=${EVAL_OUTPUT:-$REPO/eval_output}
THREADS=${EVAL_THREADS:-0}
SKIP=" ${EVAL_SKIP:-} "
RAW="$OUT/raw"
LOGS="$OUT/logs"

# Depth models of the tables. The GP on LiDAR input uses the documented tile approximation: the
# exact GP takes about a minute per frame on 1-in-4 LiDAR even at stride 4 (measured 58 s).
RADAR_MODELS=(local_gp_mle ground_gp kernel nearest linear ipbasic constant)
LIDAR_MODELS=(local_gp_mle ground_gp kernel nearest linear ipbasic constant)
LIDAR_GP_ARGS=(--max-neighbors 64)
LIDAR_STRIDE=4
LIDAR_SUBSAMPLE=4
NVS_MODELS=(local_gp_mle ground_gp kernel nearest constant)
RETENTIONS=(40 60 80 100)

for tool in evaluate_depth complete_depth render_conditioning; do
  if [[ ! -x "$TOOLS/$tool" ]]; then
    echo "eval: $TOOLS/$tool is missing; build first (make build BUILD_DIR=...)" >&2
    exit 1
  fi
done
mkdir -p "$RAW" "$LOGS"
: > "$LOGS/eval.log"
EVAL_START=$(date +%s.%N)
elapsed() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }'; }
progress() { printf '[eval %6ss] %s\n' "$(elapsed "$EVAL_START")" "$*" >&2; }
skipped() { [[ "$SKIP" == *" $1 "* ]]; }

# Runs a tool, logging its command and stderr; stdout goes to $1 (a JSON line).
run_json() {
  local out=$1
  shift
  echo "+ $*" >> "$LOGS/eval.log"
  if ! "$@" > "$out" 2>> "$LOGS/eval.log"; then
    echo "eval: failed: $*" >&2
    tail -n 5 "$LOGS/eval.log" >&2
    exit 1
  fi
}

# depth_tables SUITE ROOT FRAMES: tables 1-3 of one suite.
depth_tables() {
  local suite=$1 root=$2 frames=$3 dir="$RAW/$1"
  mkdir -p "$dir"
  local common=(--vod-root "$root" --frames "$frames" --threads "$THREADS")
  for model in "${RADAR_MODELS[@]}"; do
    progress "$suite: radar input, $model"
    run_json "$dir/radar_$model.line" "$TOOLS/evaluate_depth" "${common[@]}" --input radar \
      --model "$model" --retain-percent 100,80,60,40 --output "$dir/radar_$model.json"
  done
  for model in "${LIDAR_MODELS[@]}"; do
    progress "$suite: LiDAR 1-in-$LIDAR_SUBSAMPLE input, $model"
    local extra=()
    [[ "$model" == local_gp_mle ]] && extra=("${LIDAR_GP_ARGS[@]}")
    run_json "$dir/lidar_$model.line" "$TOOLS/evaluate_depth" "${common[@]}" --input lidar \
      --subsample "$LIDAR_SUBSAMPLE" --stride "$LIDAR_STRIDE" --model "$model" "${extra[@]}" \
      --retain-percent 100,80 --output "$dir/lidar_$model.json"
  done
  for radius in 1 4; do
    progress "$suite: radius ablation r = $radius deg"
    run_json "$dir/radius_$radius.line" "$TOOLS/evaluate_depth" "${common[@]}" --input radar \
      --model local_gp_mle --radius-deg "$radius" --retain-percent 100,80 \
      --output "$dir/radius_$radius.json"
  done
}

# nvs_table SUITE ROOT FIRST LAST SIZE_H SIZE_W: table 4 of one suite.
nvs_table() {
  local suite=$1 root=$2 first=$3 last=$4 dir="$RAW/$1/nvs"
  local size=("$5" "$6")
  local fid count
  fid=$(printf "%05d" "$first")
  count=$((last - first + 1))
  mkdir -p "$dir"
  for model in "${NVS_MODELS[@]}"; do
    for retain in "${RETENTIONS[@]}"; do
      progress "$suite: novel view, $model at $retain %"
      local prefix="$dir/${model}_$retain"
      run_json "$prefix.depth.json" "$TOOLS/complete_depth" --vod-root "$root" --frame "$fid" \
        --sensor radar --model "$model" --retain-percent "$retain" --threads "$THREADS" \
        --output "$prefix"
      run_json "$prefix.render.json" "$TOOLS/render_conditioning" \
        --image "$root/lidar/training/image_2/$fid.jpg" --depth "${prefix}_depth.npy" \
        --valid "${prefix}_valid.npy" --calib "$root/radar/training/calib/$fid.txt" \
        --vod-root "$root" --frames "$first-$last" --num-frames "$count" \
        --size "${size[@]}" --threads "$THREADS" --output "$prefix.render"
      cp "$prefix.render/metrics.json" "$prefix.metrics.json"
      rm -f "${prefix}_depth.npy" "${prefix}_variance.npy" "${prefix}_valid.npy"
      if [[ "${EVAL_KEEP_FRAMES:-0}" != 1 ]]; then
        rm -rf "$prefix.render"
      fi
    done
  done
}

# --- View-of-Delft ---------------------------------------------------------------------------
VOD="$DATA/vod"
if skipped vod; then
  progress "VoD suite skipped (EVAL_SKIP)"
elif [[ ! -d "$VOD/lidar/training/velodyne" ]]; then
  progress "VoD suite skipped: no View-of-Delft data in $VOD (set MMNVS_DATA_DIR)"
else
  VOD=$(cd "$VOD" && pwd)
  rm -rf "$RAW/vod"
  depth_tables vod "$VOD" 549,1047
  if skipped nvs; then
    progress "vod: novel view skipped (EVAL_SKIP)"
  elif [[ -f "$VOD/radar/training/velodyne/08350.bin" ]]; then
    nvs_table vod "$VOD" 8350 8365 704 1280
  else
    progress "vod: novel view skipped: no radar scan of frame 08350"
  fi
fi

# --- synthetic street ------------------------------------------------------------------------
# Scale 0.5 (968x608), 16 frames, seed 1; depth against the exact depth_gt images. Its novel-view
# table renders at 352x640 (GEN3C's scatter of a 968-wide image into 1280 columns leaves holes;
# make demo makes the same choice).
SYN="$OUT/synthetic_scene"
if skipped synthetic; then
  progress "synthetic suite skipped (EVAL_SKIP)"
elif [[ ! -x "$TOOLS/make_synthetic_scene" ]]; then
  progress "synthetic suite skipped: $TOOLS/make_synthetic_scene is not built"
else
  # The cache is reused only if it was generated with exactly these settings (keys in any order).
  if [[ "${EVAL_REGENERATE:-0}" == 1 || ! -f "$SYN/scene.json" ]] ||
     ! "$PY" -c 'import json, sys
s = json.load(open(sys.argv[1]))
sys.exit(0 if (s.get("frames"), s.get("first_frame"), s.get("seed"), s.get("width")) == (16, 0, 1, 968) else 1)' \
       "$SYN/scene.json"; then
    progress "synthetic: generating the scene (16 frames, scale 0.5)"
    rm -rf "$SYN"
    run_json "$LOGS/make_synthetic_scene.json" "$TOOLS/make_synthetic_scene" --output "$SYN" \
      --num-frames 16 --scale 0.5 --seed 1 --threads "$THREADS" --quiet
  else
    progress "synthetic: reusing the cached scene in $SYN"
  fi
  rm -rf "$RAW/synthetic"
  depth_tables synthetic "$SYN" 0,5,10,15
  if skipped nvs; then
    progress "synthetic: novel view skipped (EVAL_SKIP)"
  else
    nvs_table synthetic "$SYN" 0 15 352 640
  fi
fi

progress "tables"
EVAL_SECONDS=$(elapsed "$EVAL_START")
"$PY" "$REPO/scripts/eval_tables.py" tables "$OUT" --seconds "$EVAL_SECONDS" \
  --threads "$(nproc)"
progress "done: $OUT/tables.md, $OUT/tables.json"
