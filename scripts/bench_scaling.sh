#!/usr/bin/env bash
# The README's scaling table in one command: runs bench_scaling (bench/bench_scaling.cpp; the
# default radar and LiDAR models of config/*.yaml on synthetic scans) with BENCH_REPETITIONS runs
# per case (default 3) and prints the medians as a Markdown table.
# Usage: scripts/bench_scaling.sh [BUILD_DIR]   (after `make build`)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
BIN=$(scripts/devel_dir.sh "$BUILD_DIR")/lib/multimodal_nvs/bench_scaling
OUT=$BUILD_DIR/bench
mkdir -p "$OUT"
"$BIN" --benchmark_repetitions="${BENCH_REPETITIONS:-3}" --benchmark_report_aggregates_only=true \
  --benchmark_out="$OUT/bench_scaling.json" --benchmark_out_format=json > "$OUT/bench_scaling.log"
/usr/bin/python3 - "$OUT/bench_scaling.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
print("load average: %s" % ", ".join("%.2f" % x for x in report["context"].get("load_avg", [])))
print("| model (config) | returns in view | image (% of 1936x1216 px) | stride | grid pixels | neighbour sets | median ms |")
print("|---|---|---|---|---|---|---|")
for b in report["benchmarks"]:
    if b.get("aggregate_name") != "median":
        continue
    name = b["run_name"].split("/")
    model = "radar.yaml" if name[0] == "BM_RadarDefault" else "lidar.yaml"
    pct = [p.split(":")[1] for p in name if p.startswith("image_pct:")][0]
    print("| %s | %d | %s | %d | %.2fM | %d | %.1f |" % (
        model, round(b["in_view"]), pct, round(b["stride"]), b["grid_px"] / 1e6, round(b["sets"]),
        b["real_time"]))
PY
