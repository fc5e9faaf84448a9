#!/usr/bin/env bash
# `make bench`: every benchmark of the package, medians only. Usage: bench/run_benchmarks.sh [BUILD_DIR]
#   1. each Google Benchmark binary built from bench/*.cpp and bench/ros_conversions/*.cpp,
#      BENCH_REPETITIONS runs per case (default 5); prints one line per case with the median real
#      and CPU time;
#   2. the node latency harnesses: bench/ros/bench_depth_node.sh at stride 1 and 2 (median node
#      latency, end-to-end latency and compute time of 150 sets at 15 Hz) and
#      bench/ros/bench_renderer.sh at stride 2 (median render, callback and end-to-end times);
#   3. bench/bench_render_conditioning.sh: median wall time of render_conditioning's GEN3C export.
# Cases on ../shared/data (MMNVS_DATA_DIR) report "data not found" instead of a time when the data
# is missing; BENCH_NODE=0 skips the node harnesses.
set -uo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
BIN=$(scripts/devel_dir.sh "$BUILD_DIR")/lib/multimodal_nvs
REPETITIONS=${BENCH_REPETITIONS:-5}
export PATH=/usr/bin:/bin:$PATH
OUT=$BUILD_DIR/bench
mkdir -p "$OUT"
status=0

for source in bench/*.cpp bench/ros_conversions/*.cpp; do
  name=$(basename "$source" .cpp)
  if [[ ! -x "$BIN/$name" ]]; then
    echo "[bench] $name: not built (Debian's libbenchmark-dev missing?)" >&2
    status=1
    continue
  fi
  echo "[bench] $name: $REPETITIONS repetitions per case"
  "$BIN/$name" --benchmark_repetitions="$REPETITIONS" --benchmark_report_aggregates_only=true \
    --benchmark_out="$OUT/$name.json" --benchmark_out_format=json > "$OUT/$name.log" 2>&1 ||
    { echo "[bench] $name FAILED (log: $OUT/$name.log)" >&2; status=1; continue; }
  /usr/bin/python3 - "$OUT/$name.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
for b in report["benchmarks"]:
    if b.get("error_occurred"):
        print("  %-48s %s" % (b["run_name"], b.get("error_message", "error")))
    elif b.get("aggregate_name") == "median":
        print("  %-48s median %9.2f %s real, %9.2f %s CPU" % (
            b["run_name"], b["real_time"], b["time_unit"], b["cpu_time"], b["time_unit"]))
PY
done

echo "[bench] bench_render_conditioning: the GEN3C export of VoD 08350 (121 frames), 3 runs"
bench/bench_render_conditioning.sh "$BUILD_DIR" 3 || { echo "[bench] bench_render_conditioning FAILED" >&2; status=1; }

if [[ "${BENCH_NODE:-1}" != 0 ]]; then
  echo "[bench] bench_depth_node: the standalone node fed VoD 08350 at 15 Hz, stride 1 and 2"
  bench/ros/bench_depth_node.sh "$BUILD_DIR" 1 2 || { echo "[bench] bench_depth_node FAILED" >&2; status=1; }
  echo "[bench] bench_renderer: the standalone renderer in tf mode, 1216x1936 camera at 5 Hz"
  bench/ros/bench_renderer.sh "$BUILD_DIR" 2 || { echo "[bench] bench_renderer FAILED" >&2; status=1; }
fi
exit $status
