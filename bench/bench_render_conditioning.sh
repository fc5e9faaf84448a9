#!/usr/bin/env bash
# Wall time of render_conditioning's whole GEN3C export (not a test): the paper's experiment on VoD
# 08350 (keyframe 08350, recorded poses 08350-08365 resampled to 121 frames at 704x1280, --gen3c:
# 1.7 GB of arrays, 363 PNGs, the preview video). Runs the tool REPEATS times into OUTPUT_DIR (a
# normal directory on disk by default; give /dev/shm/... to leave the disk out) and prints the
# median wall, user and system seconds (/usr/bin/time) and the tool's render_ms. Usage:
#   bench/bench_render_conditioning.sh [BUILD_DIR] [REPEATS=5] [OUTPUT_DIR=BUILD_DIR/bench/export]
# Environment: THREADS (0: all cores), MMNVS_DATA_DIR (../shared/data).
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
REPEATS=${2:-5}
OUT=${3:-$BUILD_DIR/bench/export}
BIN=$(scripts/devel_dir.sh "$BUILD_DIR")/lib/multimodal_nvs
VOD=${MMNVS_DATA_DIR:-$(pwd)/../shared/data}/vod
if [[ ! -f "$VOD/lidar/training/image_2/08350.jpg" ]]; then
  echo "render_conditioning export: VoD data not found under $VOD (set MMNVS_DATA_DIR)"
  exit 0
fi
mkdir -p "$OUT"
# The keyframe's depth: complete_depth's default radar model at full resolution.
"$BIN/complete_depth" --vod-root "$VOD" --frame 8350 --sensor radar --output "$OUT/08350" \
  --quiet > /dev/null || { echo "complete_depth failed" >&2; exit 1; }
for ((i = 0; i < REPEATS; ++i)); do
  rm -rf "$OUT/render"
  /usr/bin/time -f "%e %U %S" -o "$OUT/time.$i" "$BIN/render_conditioning" \
    --image "$VOD/lidar/training/image_2/08350.jpg" --depth "$OUT/08350_depth.npy" \
    --valid "$OUT/08350_valid.npy" --calib "$VOD/radar/training/calib/08350.txt" \
    --vod-root "$VOD" --frames 8350-8365 --num-frames 121 --gen3c --threads "${THREADS:-0}" \
    --output "$OUT/render" --quiet > "$OUT/render.$i.json" || { echo "render_conditioning failed" >&2; exit 1; }
done
rm -rf "$OUT/render"
/usr/bin/python3 - "$OUT" "$REPEATS" <<'PY'
import json, statistics, sys
out, n = sys.argv[1], int(sys.argv[2])
times = [list(map(float, open(f"{out}/time.{i}").read().split()[-3:])) for i in range(n)]
render = [json.loads(open(f"{out}/render.{i}.json").read())["render_ms"] for i in range(n)]
med = lambda xs: statistics.median(xs)
print("render_conditioning export, VoD 08350, 121 frames 704x1280, %d runs: median wall %.2f s, "
      "user %.2f s, sys %.2f s, render %.2f s (walls: %s)" % (
          n, med([t[0] for t in times]), med([t[1] for t in times]), med([t[2] for t in times]),
          med(render) / 1000.0, " ".join("%.1f" % t[0] for t in times)))
PY
