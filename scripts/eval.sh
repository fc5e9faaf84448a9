#!/usr/bin/env bash
# make eval: depth and novel-view (NVS) tables of every depth model, with the baselines side by
# side, on the synthetic scenes of eval/synthetic_scenes.tsv (exact depth, so an oracle row) and
# on the real frames in the shared data directory. Writes eval_output/tables.md + tables.json
# (every raw JSON under eval_output/raw/) and prints the tables.
#
#   scripts/eval.sh BUILD_DIR
#
# Quick scoring of some models on one split of the synthetic scenes (per scene and mean novel-view
# covered PSNR / coverage / preview PSNR, the gap to the exact-depth oracle, depth MAE, runtime):
#
#   EVAL_SPLIT=dev EVAL_MODELS="ground_gp nearest" EVAL_SKIP="vod real" scripts/eval.sh build
#
# Tune on the dev scenes only; the validation scenes are for reporting (eval/synthetic_scenes.tsv
# says which is which).
#
# Environment:
#   MMNVS_DATA_DIR   real data (default <repo>/../shared/data)
#   EVAL_OUTPUT      output directory (default <repo>/eval_output)
#   EVAL_SPLIT       dev|validation|all: synthetic scenes to run (default all)
#   EVAL_SCENES      space-separated scene names (default: every scene of the split)
#   EVAL_MODELS      space-separated depth models (default: all seven below)
#   EVAL_NVS_MODELS  the models whose depth is also rendered into novel views (default: EVAL_MODELS;
#                    a render costs about ten depth runs)
#   EVAL_SKIP        space-separated suites to skip: synthetic, vod, real (= astyx nuscenes kitti
#                    distorted_camera), each of those by name, nvs (no novel views), oracle (no
#                    oracle renders), lidar (no LiDAR input), ablation (VoD radius ablation)
#   EVAL_THREADS     worker threads (0 = all cores)
#   EVAL_SCENE_CACHE where generated scenes are kept (default $EVAL_OUTPUT/scenes); a scene is
#                    regenerated only when its arguments, scale or frame count change
#   EVAL_SCENE_SCALE image scale of the synthetic scenes (default 0.5: 968x608)
#   EVAL_RETENTION   retention (%) of the novel-view depth (default: each sensor's retain_percent
#                    in config/radar.yaml and config/lidar.yaml); VoD 08350 also at 80 and 100
#   EVAL_MODEL_ARGS  extra options of every depth run (tuning on dev: "--guided-lambda 1000")
#   EVAL_SCENE_ARGS  extra make_synthetic_scene options of every scene (part of the cache key), e.g.
#                    "--radar-ghosts 0.5 --radar-ghost-max-factor 3" (a radar like the real ones)
#   EVAL_SCENE_DEPTH_FRAMES frames of the synthetic depth metrics (default 0, the novel-view frame)
#   EVAL_KEEP_FRAMES=1 keeps the rendered frames of the novel-view runs
#
# Suites:
#   synthetic  per scene: depth from radar and from LiDAR (1-in-4 returns as input) against the
#              exact depth at frame 0 (all pixels and kept 80 %); novel views from frame
#              0's depth (radar, and all LiDAR returns) rendered with GEN3C's splatting into the
#              16 recorded poses at 352x640, next to the oracle: the exact depth with the sky at
#              GEN3C's 100 m clamp (and the exact depth with the sky dropped).
#   vod        00549/01047: radar and LiDAR (1-in-4 input, the rest as ground truth) depth, the
#              radius and retention ablations; 08350: novel views into 08350-08365 at 704x1280
#              (radar, 80 and 100 % retention) along the map poses (the reference's) and the
#              odometry poses. No oracle: no exact depth.
#   astyx, nuscenes, distorted_camera (VoD layout, no poses), kitti (KITTI object layout, LiDAR
#              only; skipped with the reason while the tools cannot read that layout): depth
#              from radar (where the folder has radar) and from LiDAR (1-in-4 input, the rest as
#              ground truth), runtime per frame.
#              A model that fails is listed with its reason (e.g. "needs pose"), the rest go on.
# The recorded poses only are rendered (16 frames): GEN3C's 121-frame trajectory puts them at
# frames 0, 8, ..., 120, so the metrics equal those of the full render.
set -euo pipefail
# The whole script is one block, read before it runs: editing the file during a long evaluation
# cannot change what the running one does.
{
BUILD_DIR=${1:-build}
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$REPO"
if [[ ! -d "$BUILD_DIR" ]]; then
  echo "eval: build directory '$BUILD_DIR' does not exist (run 'make eval' or 'make build')" >&2
  exit 2
fi
BUILD_DIR=$(cd "$BUILD_DIR" && pwd)
DEVEL=$("$REPO/scripts/devel_dir.sh" "$BUILD_DIR")
TOOLS="$DEVEL/lib/multimodal_nvs"
PY=/usr/bin/python3
DATA=${MMNVS_DATA_DIR:-$REPO/../shared/data}
OUT=${EVAL_OUTPUT:-$REPO/eval_output}
THREADS=${EVAL_THREADS:-0}
SPLIT=${EVAL_SPLIT:-all}
SKIP=" ${EVAL_SKIP:-} "
RAW="$OUT/raw"
LOGS="$OUT/logs"
SCENE_LIST="$REPO/eval/synthetic_scenes.tsv"
SCENE_CACHE=${EVAL_SCENE_CACHE:-$OUT/scenes}
SCENE_SCALE=${EVAL_SCENE_SCALE:-0.5}
SCENE_FRAMES=16
SCENE_DEPTH_FRAMES=${EVAL_SCENE_DEPTH_FRAMES:-0}
# Novel-view retention per input: the configs' unless EVAL_RETENTION sets one for both.
RADAR_RETENTION=${EVAL_RETENTION:-$("$REPO/scripts/config_value.sh" radar retain_percent)}
LIDAR_RETENTION=${EVAL_RETENTION:-$("$REPO/scripts/config_value.sh" lidar retain_percent)}

# Depth models of the tables. On LiDAR input the GP uses the documented tile approximation (the
# exact GP takes about a minute per frame on 1-in-4 LiDAR even at stride 4: measured 58 s).
read -r -a MODELS <<< "${EVAL_MODELS:-local_gp_mle ground_gp image_guided kernel nearest linear ipbasic constant}"
read -r -a NVS_MODELS <<< "${EVAL_NVS_MODELS:-${MODELS[*]}}"
LIDAR_GP_ARGS=(--max-neighbors 64)
# Kernel regression on all LiDAR returns (the novel views): a 1 deg radius (its 2 deg radius holds
# thousands of returns per pixel: 40 s per frame at 968x608 on a loaded machine, 8 s with 1 deg).
LIDAR_KERNEL_ARGS=(--radius-deg 1)
LIDAR_STRIDE=4
LIDAR_SUBSAMPLE=4
# ground_gp on LiDAR input, depth and novel views alike, leaves out the returns the camera cannot
# see as config/lidar.yaml does: on the synthetic scenes' exact depth that is what the camera sees
# (the real data's projected-LiDAR truth still holds those returns, which costs VoD; README).
# lidar.yaml's sky only in the novel views: under the 1-in-4 protocol the truth has returns above
# the input's highest ring, where the sky test looks (README, "ground_gp and the sky").
LIDAR_GROUND_GP_ARGS=(--drop-hidden-returns
  "$("$REPO/scripts/config_value.sh" lidar ground_drop_hidden_returns)")

case "$SPLIT" in
  dev | validation | all) ;;
  *) echo "eval: EVAL_SPLIT must be dev, validation or all, got '$SPLIT'" >&2; exit 2 ;;
esac
for tool in evaluate_depth complete_depth render_conditioning make_synthetic_scene; do
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
skipped() {
  local name
  for name in "$@"; do
    [[ "$SKIP" == *" $name "* ]] && return 0
  done
  return 1
}

# Runs a tool, logging its command and stderr; stdout goes to $1 (a JSON line). Exits on failure.
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

# Like run_json, but a failure is recorded in $1.error (the tool's last error line) and returns 1,
# so that one model that cannot run on a dataset (e.g. one that needs a pose) does not end the
# evaluation; the tables list it with the reason.
try_json() {
  local out=$1
  shift
  echo "+ $*" >> "$LOGS/eval.log"
  rm -f "$out.error"
  local err
  err=$(mktemp)
  if "$@" > "$out" 2> "$err"; then
    cat "$err" >> "$LOGS/eval.log"
    rm -f "$err"
    return 0
  fi
  cat "$err" >> "$LOGS/eval.log"
  grep -v '^\s*$' "$err" | tail -n 1 > "$out.error" || true
  [[ -s "$out.error" ]] || echo "exit status non-zero, no message" > "$out.error"
  progress "  failed ($(cat "$out.error")); listed in the tables"
  rm -f "$err" "$out"
  return 1
}

# model_args MODEL INPUT [all]: extra arguments of a model on LiDAR input ("all": every return,
# as the novel views use, rather than 1 in 4), then EVAL_MODEL_ARGS (every depth run).
model_args() {
  [[ "$1" == local_gp_mle && "$2" == lidar ]] && echo "${LIDAR_GP_ARGS[@]}"
  [[ "$1" == kernel && "$2" == lidar && "${3:-}" == all ]] && echo "${LIDAR_KERNEL_ARGS[@]}"
  [[ "$1" == ground_gp && "$2" == lidar ]] && echo "${LIDAR_GROUND_GP_ARGS[@]}"
  # The novel views from all LiDAR returns run ground_gp as config/lidar.yaml does, with its sky.
  [[ "$1" == ground_gp && "$2" == lidar && "${3:-}" == all ]] &&
    echo "--ground-image-sky $("$REPO/scripts/config_value.sh" lidar ground_image_sky)"
  echo "${EVAL_MODEL_ARGS:-}"
}

# depth_runs SUITE ROOT FRAMES INPUTS RADAR_STRIDE [ROOT_OPTION]: depth from each input, every
# model, all pixels and kept 80 %. ROOT_OPTION names the layout option (--vod-root).
depth_runs() {
  local suite=$1 root=$2 frames=$3 inputs=$4 radar_stride=$5 root_option=${6:---vod-root}
  local dir="$RAW/$suite" model input
  mkdir -p "$dir"
  local common=("$root_option" "$root" --frames "$frames" --threads "$THREADS")
  for input in $inputs; do
    for model in "${MODELS[@]}"; do
      progress "$suite: depth from $input, $model"
      # shellcheck disable=SC2046
      if [[ "$input" == radar ]]; then
        try_json "$dir/radar_$model.line" "$TOOLS/evaluate_depth" "${common[@]}" --input radar \
          --model "$model" $(model_args "$model" radar) --stride "$radar_stride" \
          --retain-percent 100,80,60,40 --save-errors "$dir/errors/radar_$model" \
          --output "$dir/radar_$model.json" || rm -f "$dir/radar_$model.json"
      else
        try_json "$dir/lidar_$model.line" "$TOOLS/evaluate_depth" "${common[@]}" --input lidar \
          --subsample "$LIDAR_SUBSAMPLE" --stride "$LIDAR_STRIDE" --model "$model" \
          $(model_args "$model" lidar) --retain-percent 100,80 \
          --save-errors "$dir/errors/lidar_$model" \
          --output "$dir/lidar_$model.json" || rm -f "$dir/lidar_$model.json"
      fi
    done
  done
  # Every model's MAE on the pixels that all of them predict (<input>_common.json; the per-pixel
  # errors are removed afterwards).
  "$PY" "$REPO/scripts/eval_tables.py" common "$dir"
}

# render_nvs PREFIX IMAGE CALIB ROOT FIRST LAST H W [POSE_KEY OUT]: renders PREFIX_depth.npy
# (+ PREFIX_valid.npy) into the recorded poses FIRST..LAST; metrics to OUT.metrics.json, the tool's
# line to OUT.render.json (OUT: PREFIX unless given). POSE_KEY: which transform of the VoD pose
# files is the trajectory (default: the tool's, mapToCamera as the reference renderer).
render_nvs() {
  local prefix=$1 image=$2 calib=$3 root=$4 first=$5 last=$6 out=${10:-$1}
  local valid=() pose=()
  [[ -f "${prefix}_valid.npy" ]] && valid=(--valid "${prefix}_valid.npy")
  [[ -n "${9:-}" ]] && pose=(--pose-key "$9")
  try_json "$out.render.json" "$TOOLS/render_conditioning" --image "$image" \
    --depth "${prefix}_depth.npy" "${valid[@]}" --calib "$calib" --vod-root "$root" \
    --frames "$first-$last" --num-frames $((last - first + 1)) --size "$7" "$8" "${pose[@]}" \
    --threads "$THREADS" --output "$out.render" || return 0
  cp "$out.render/metrics.json" "$out.metrics.json"
  if [[ "${EVAL_KEEP_FRAMES:-0}" != 1 ]]; then
    rm -rf "$out.render"
  fi
}

# nvs_model_runs DIR ROOT FRAME_ID INPUT RETENTIONS FIRST LAST H W [ALSO_POSE_KEY]: depth of frame
# FRAME_ID from INPUT by every model at each retention, rendered into FIRST..LAST; with
# ALSO_POSE_KEY also along that transform of the pose files (to PREFIX.<key>.metrics.json).
nvs_model_runs() {
  local dir=$1 root=$2 fid=$3 input=$4 retentions=$5 first=$6 last=$7 h=$8 w=$9 also=${10:-}
  local model retain
  mkdir -p "$dir"
  for model in "${NVS_MODELS[@]}"; do
    for retain in $retentions; do
      progress "${dir#"$RAW"/}: novel view, $input -> $model at $retain %"
      local prefix="$dir/${input}_${model}_$retain"
      # shellcheck disable=SC2046
      if try_json "$prefix.depth.json" "$TOOLS/complete_depth" --vod-root "$root" --frame "$fid" \
        --sensor "$input" --model "$model" $(model_args "$model" "$input" all) \
        --retain-percent "$retain" --threads "$THREADS" --output "$prefix"; then
        local pose
        for pose in "" ${also:+"$also"}; do
          render_nvs "$prefix" "$root/lidar/training/image_2/$fid.jpg" \
            "$root/$input/training/calib/$fid.txt" "$root" "$first" "$last" "$h" "$w" \
            "$pose" "$prefix${pose:+.$pose}"
        done
      fi
      rm -f "${prefix}_depth.npy" "${prefix}_variance.npy" "${prefix}_valid.npy"
    done
  done
}

# --- synthetic scenes ------------------------------------------------------------------------
# make_scene NAME ARGS...: the scene in $SCENE_CACHE/NAME, generated unless cached with the same
# arguments.
make_scene() {
  local name=$1
  shift
  local dir="$SCENE_CACHE/$name"
  local key="$* --num-frames $SCENE_FRAMES --scale $SCENE_SCALE"
  if [[ "${EVAL_REGENERATE:-0}" != 1 && -f "$dir/eval_args.txt" && -f "$dir/scene.json" &&
        "$(cat "$dir/eval_args.txt")" == "$key" ]]; then
    progress "synthetic/$name: reusing the cached scene"
    return 0
  fi
  progress "synthetic/$name: generating ($key)"
  rm -rf "$dir"
  # shellcheck disable=SC2086
  run_json "$LOGS/make_scene_$name.json" "$TOOLS/make_synthetic_scene" --output "$dir" \
    --num-frames "$SCENE_FRAMES" --scale "$SCENE_SCALE" --threads "$THREADS" --quiet "$@"
  printf '%s' "$key" > "$dir/eval_args.txt"
}

# The oracle: frame 0's exact depth with the sky at GEN3C's 100 m clamp ("oracle"), and with the
# sky dropped ("exact_nosky").
oracle_runs() {
  local dir=$1 root=$2
  mkdir -p "$dir"
  "$PY" - "$root/depth_gt/00000.npy" "$dir" <<'EOF'
import sys
import numpy as np
depth = np.load(sys.argv[1]).astype(np.float32)
sky = ~(depth > 0)
np.save(sys.argv[2] + "/oracle_depth.npy", np.where(sky, np.float32(100.0), depth))
np.save(sys.argv[2] + "/exact_nosky_depth.npy", np.where(sky, np.float32(0.0), depth))
EOF
  local kind
  for kind in oracle exact_nosky; do
    progress "${dir#"$RAW"/}: novel view, $kind"
    render_nvs "$dir/$kind" "$root/lidar/training/image_2/00000.jpg" \
      "$root/radar/training/calib/00000.txt" "$root" 0 $((SCENE_FRAMES - 1)) 352 640
    rm -f "$dir/${kind}_depth.npy"
  done
}

if skipped synthetic; then
  progress "synthetic scenes skipped (EVAL_SKIP)"
else
  rm -rf "$RAW/synthetic"
  mkdir -p "$RAW/synthetic" "$SCENE_CACHE"
  # The tables name them: scenes made with other sensors than the list's are other scenes.
  [[ -n "${EVAL_SCENE_ARGS:-}" ]] && printf '%s\n' "$EVAL_SCENE_ARGS" > "$RAW/synthetic/scene_args.txt"
  scene_count=0
  while IFS=$'\t' read -r name split args; do
    [[ -z "$name" || "$name" == \#* ]] && continue
    [[ "$SPLIT" != all && "$split" != "$SPLIT" ]] && continue
    if [[ -n "${EVAL_SCENES:-}" && " $EVAL_SCENES " != *" $name "* ]]; then continue; fi
    scene_count=$((scene_count + 1))
    read -r -a scene_args <<< "$args ${EVAL_SCENE_ARGS:-}"
    make_scene "$name" "${scene_args[@]}"
    root="$SCENE_CACHE/$name"
    dir="$RAW/synthetic/$name"
    mkdir -p "$dir"
    printf '{"name": "%s", "split": "%s", "args": "%s", "scale": %s, "frames": %s}\n' \
      "$name" "$split" "${scene_args[*]}" "$SCENE_SCALE" "$SCENE_FRAMES" > "$dir/scene.json"
    inputs="radar"
    skipped lidar || inputs="radar lidar"
    depth_runs "synthetic/$name" "$root" "$SCENE_DEPTH_FRAMES" "$inputs" 1
    if ! skipped nvs; then
      skipped oracle || oracle_runs "$dir/nvs" "$root"
      for input in $inputs; do
        retention=$RADAR_RETENTION
        [[ "$input" == lidar ]] && retention=$LIDAR_RETENTION
        nvs_model_runs "$dir/nvs" "$root" 00000 "$input" "$retention" 0 \
          $((SCENE_FRAMES - 1)) 352 640
      done
    fi
  done < "$SCENE_LIST"
  if [[ $scene_count == 0 ]]; then
    echo "eval: no scene of split '$SPLIT' in $SCENE_LIST (EVAL_SCENES='${EVAL_SCENES:-}')" >&2
    exit 2
  fi
fi

# --- View-of-Delft ---------------------------------------------------------------------------
VOD="$DATA/vod"
if skipped vod; then
  progress "VoD suite skipped (EVAL_SKIP)"
elif [[ ! -d "$VOD/lidar/training/velodyne" ]]; then
  progress "VoD suite skipped: no View-of-Delft data in $VOD (set MMNVS_DATA_DIR)"
else
  VOD=$(cd "$VOD" && pwd)
  rm -rf "$RAW/vod"
  inputs="radar"
  skipped lidar || inputs="radar lidar"
  depth_runs vod "$VOD" 549,1047 "$inputs" 1
  if ! skipped ablation && [[ " ${MODELS[*]} " == *" local_gp_mle "* ]]; then
    for radius in 1 4; do
      progress "vod: radius ablation r = $radius deg"
      run_json "$RAW/vod/radius_$radius.line" "$TOOLS/evaluate_depth" --vod-root "$VOD" \
        --frames 549,1047 --threads "$THREADS" --input radar --model local_gp_mle \
        --radius-deg "$radius" --retain-percent 100,80 --output "$RAW/vod/radius_$radius.json"
    done
  fi
  if skipped nvs; then
    progress "vod: novel view skipped (EVAL_SKIP)"
  elif [[ -f "$VOD/radar/training/velodyne/08350.bin" ]]; then
    # Also along the odometry poses: VoD's map poses (the reference renderer's trajectory) carry
    # the localisation's corrections (on 08350-08365 their rotation since 08350 differs from the
    # odometry's by 0.04-0.53 deg, jumping between neighbouring frames); REP 105: the odom frame
    # is continuous, the map frame may jump.
    nvs_model_runs "$RAW/vod/nvs" "$VOD" 08350 radar \
      "$(printf '%s\n' 80 100 "$RADAR_RETENTION" | sort -nu | tr '\n' ' ')" 8350 8365 704 1280 \
      odomToCamera
  else
    progress "vod: novel view skipped: no radar scan of frame 08350"
  fi
fi

# --- other real data (VoD layout without poses, KITTI layout) --------------------------------
# frames_of DIR: the frame numbers of a VoD-layout folder (from its images), comma-separated.
frames_of() {
  find "$1/lidar/training/image_2" -maxdepth 1 -name '*.jpg' -printf '%f\n' | sed 's/\.jpg$//' |
    sed 's/^0*\([0-9]\)/\1/' | sort -n | paste -sd, -
}

real_suite() {  # real_suite NAME STRIDE
  local name=$1 stride=$2 root="$DATA/$1"
  if skipped real "$name"; then
    progress "$name suite skipped (EVAL_SKIP)"
    return 0
  fi
  if [[ ! -d "$root/lidar/training/velodyne" ]]; then
    progress "$name suite skipped: no data in $root"
    return 0
  fi
  root=$(cd "$root" && pwd)
  rm -rf "${RAW:?}/$name"
  local inputs=""
  [[ -d "$root/radar/training/velodyne" ]] && inputs="radar"
  skipped lidar || inputs="$inputs lidar"
  depth_runs "$name" "$root" "$(frames_of "$root")" "$inputs" "$stride"
}

# Astyx: ~1,000 radar returns per frame (the exact GP takes seconds per frame): stride 2.
real_suite astyx 2
real_suite nuscenes 2
real_suite distorted_camera 2

# KITTI object layout (LiDAR only): runs once the tools read that layout from --vod-root (the
# layout is told from the folder) or a --kitti-root option; a one-frame probe decides.
KITTI="$DATA/kitti"
if skipped real kitti lidar; then
  progress "kitti suite skipped (EVAL_SKIP)"
elif [[ ! -d "$KITTI/velodyne" ]]; then
  progress "kitti suite skipped: no data in $KITTI"
else
  KITTI=$(cd "$KITTI" && pwd)
  rm -rf "$RAW/kitti"
  kitti_frames=$(find "$KITTI/velodyne" -maxdepth 1 -name '*.bin' -printf '%f\n' |
    sed 's/\.bin$//; s/^0*\([0-9]\)/\1/' | sort -n | paste -sd, -)
  kitti_option=--vod-root
  "$TOOLS/evaluate_depth" --help 2>&1 | grep -q -- '--kitti-root' && kitti_option=--kitti-root
  if probe=$("$TOOLS/evaluate_depth" "$kitti_option" "$KITTI" --frames "${kitti_frames%%,*}" \
      --input lidar --subsample 4 --stride 8 --model nearest 2>&1 >/dev/null); then
    depth_runs kitti "$KITTI" "$kitti_frames" lidar 1 "$kitti_option"
  else
    progress "kitti suite skipped: evaluate_depth does not read the KITTI object layout yet" \
      "($(echo "$probe" | tail -n 1))"
  fi
fi

progress "tables"
EVAL_SECONDS=$(elapsed "$EVAL_START")
"$PY" "$REPO/scripts/eval_tables.py" tables "$OUT" --seconds "$EVAL_SECONDS" \
  --threads "$(nproc)" --split "$SPLIT" --lidar-ground-gp-args "${LIDAR_GROUND_GP_ARGS[*]}"
progress "done: $OUT/tables.md, $OUT/tables.json"
exit 0
}
