#!/usr/bin/python3
"""Tables of `make eval` and merging of `evaluate_depth --shard` outputs (numpy only).

  eval_tables.py tables OUT_DIR [--seconds S] [--threads N] [--split dev|validation|all]
                  [--lidar-ground-gp-args ARGS]
      Reads OUT_DIR/raw/<suite>/*.json written by scripts/eval.sh, writes OUT_DIR/tables.md and
      OUT_DIR/tables.json, and prints the Markdown. ARGS: ground_gp's own arguments on LiDAR
      input, for the captions.
  eval_tables.py common DIR [--keep]
      Reduces DIR/errors/<input>_<model>/NNNNN_errors.npy (evaluate_depth --save-errors of every
      model on the same truth) to DIR/<input>_common.json: each model's MAE and RMSE over the
      ground-truth pixels that every model predicts, per frame and as the mean over frames, and
      their share. Removes DIR/errors afterwards unless --keep.
  eval_tables.py merge MERGED.json SHARD.json [SHARD.json ...]
      Merges evaluate_depth --output files of the shards of one configuration (same config except
      the shard) into one file with the same layout; the aggregate is recomputed exactly from the
      per-frame sums.

Every aggregate here is recomputed from the per-frame records, so merged shards and single runs
give the same tables.
"""
import json
import math
import os
import shutil
import sys
import time

import numpy as np

RETENTION_NOTE = (
    " Retention keeps the given share of *all* grid pixels, lowest variance first, ties in "
    "row-major order: local GP pixels without a neighbour all have the prior variance a^2 = 625 "
    "and the constant model has one variance everywhere, so among those the top rows (sky, far) "
    "are kept and the bottom rows (road, where the ground truth is) dropped first; '–' = no "
    "ground-truth pixel kept.")
METRICS = ("mae", "rmse", "rmse_log", "abs_rel", "delta1", "coverage")
SUM_KEYS = ("gt_pixels", "count", "abs_error", "sq_error", "sq_log_error", "abs_rel", "delta1")
MODEL_NAMES = {
    "local_gp_mle": "Local GP (MLE length scale)",
    "ground_gp": "ground_gp (this package)",
    "image_guided": "image_guided (this package)",
    "kernel": "Kernel regression",
    "nearest": "Nearest sample",
    "linear": "Linear (Delaunay)",
    "ipbasic": "IP-Basic",
    "constant": "Constant (median)",
}


def fail(message):
    sys.stderr.write("eval_tables: %s\n" % message)
    sys.exit(1)


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail("%s: %s" % (path, e))


def metrics_from_sums(s):
    n = s["count"]
    nan = float("nan")
    if n == 0:
        out = {k: nan for k in METRICS}
    else:
        out = {
            "mae": s["abs_error"] / n,
            "rmse": math.sqrt(s["sq_error"] / n),
            "rmse_log": math.sqrt(s["sq_log_error"] / n),
            "abs_rel": s["abs_rel"] / n,
            "delta1": s["delta1"] / n,
        }
    out["coverage"] = n / s["gt_pixels"] if s["gt_pixels"] > 0 else nan
    out["count"] = n
    out["gt_pixels"] = s["gt_pixels"]
    return out


def aggregate(frames):
    """Per retention level: pooled metrics, mean over frames, kept; and the median runtime."""
    if not frames:
        return [], float("nan")
    levels = [r["retain_percent"] for r in frames[0]["retention"]]
    out = []
    for i, level in enumerate(levels):
        pooled = {k: 0 for k in SUM_KEYS}
        per_frame = {k: [] for k in METRICS}
        kept = 0
        for f in frames:
            r = f["retention"][i]
            if r["retain_percent"] != level:
                fail("frame %s has retention levels in a different order" % f["frame"])
            for k in SUM_KEYS:
                pooled[k] += r["sums"][k]
            kept += r["kept"]
            m = metrics_from_sums(r["sums"])
            for k in METRICS:
                per_frame[k].append(m[k])
        mean = {}
        for k in METRICS:
            values = np.array([v for v in per_frame[k] if v is not None], dtype=float)
            values = values[np.isfinite(values)]
            mean[k] = float(values.mean()) if values.size else float("nan")
        mean["frames"] = len(frames)
        entry = {"retain_percent": level, "kept": kept, "pooled": metrics_from_sums(pooled),
                 "mean_over_frames": mean, "sums": pooled}
        curves = [f["retention"][i].get("calibration") for f in frames]
        if curves and all(curves):
            count = sum(c[0]["count"] for c in curves)
            entry["calibration"] = [
                {"level": c0["level"], "inside": sum(c[j]["inside"] for c in curves),
                 "count": count,
                 "observed": sum(c[j]["inside"] for c in curves) / count if count else None}
                for j, c0 in enumerate(curves[0])]
        out.append(entry)
    runtimes = np.array([f["runtime_ms"] for f in frames if f["runtime_ms"] is not None], float)
    return out, float(np.median(runtimes)) if runtimes.size else float("nan")


def json_safe(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, list):
        return [json_safe(v) for v in value]
    return value


# ---------------------------------------------------------------------------------------------
# merge

def merge(out_path, paths):
    if not paths:
        fail("merge needs at least one shard file")
    docs = [load(p) for p in paths]
    reference = dict(docs[0]["config"])
    reference.pop("shard", None)
    frames = []
    seen = set()
    for path, doc in zip(paths, docs):
        config = dict(doc["config"])
        config.pop("shard", None)
        if config != reference:
            fail("%s: configuration differs from %s; merge only shards of one run" %
                 (path, paths[0]))
        for f in doc["frames"]:
            if f["frame"] in seen:
                fail("%s: frame %s appears in more than one shard" % (path, f["frame"]))
            seen.add(f["frame"])
            frames.append(f)
    frames.sort(key=lambda f: f["frame"])
    levels, runtime = aggregate(frames)
    merged = dict(docs[0])
    merged["config"] = dict(docs[0]["config"], shard="merged from %d files" % len(paths))
    merged["frames"] = frames
    merged["aggregate"] = levels
    merged["median_runtime_ms"] = runtime
    with open(out_path, "w") as f:
        json.dump(json_safe(merged), f, indent=1)
        f.write("\n")
    print("merged %d frames from %d shard files into %s" % (len(frames), len(paths), out_path))


# ---------------------------------------------------------------------------------------------
# tables

def common_errors(directory, keep=False):
    """evaluate_depth --save-errors of several models on one truth -> <input>_common.json.

    Models that predict only near their samples (linear inside the hull, kernel within its radius)
    are otherwise scored on easier pixels than those that predict everywhere; on the pixels that
    every model predicts the comparison is like for like. Each frame's arrays must have the same
    length (one entry per ground-truth pixel, the same truth): anything else is an error."""
    base = os.path.join(directory, "errors")
    for input_name, _ in INPUTS:  # an earlier run's result must not outlive its errors
        stale = os.path.join(directory, "%s_common.json" % input_name)
        if os.path.exists(stale):
            os.remove(stale)
    if not os.path.isdir(base):
        return
    for input_name, _ in INPUTS:
        runs = sorted(d for d in os.listdir(base) if d.startswith(input_name + "_") and
                      os.path.isdir(os.path.join(base, d)))
        frame_sets = [set(f for f in os.listdir(os.path.join(base, d)) if f.endswith("_errors.npy"))
                      for d in runs]
        # A model that failed before its first frame (the tables list it as failed) takes no part.
        runs = [d for d, f in zip(runs, frame_sets) if f]
        frame_sets = [f for f in frame_sets if f]
        models = [d[len(input_name) + 1:] for d in runs]
        if len(models) < 2:  # nothing to compare
            continue
        names = sorted(set.intersection(*frame_sets))
        frames = []
        for name in names:
            arrays = []
            for d in runs:
                path = os.path.join(base, d, name)
                try:
                    arrays.append(np.load(path).astype(np.float64).ravel())
                except (OSError, ValueError) as error:
                    fail("%s: cannot read (%s)" % (path, error))
            lengths = set(len(a) for a in arrays)
            if len(lengths) != 1:
                fail("%s: the models' error arrays differ in length (%s): not the same truth" %
                     (os.path.join(base, "*", name), ", ".join(
                         "%s %d" % (m, len(a)) for m, a in zip(models, arrays))))
            common = np.all([np.isfinite(a) for a in arrays], axis=0)
            count = int(common.sum())
            record = {"frame": int(name.split("_")[0]), "truth_pixels": int(lengths.pop()),
                      "common_pixels": count, "mae": {}, "rmse": {}}
            for model, a in zip(models, arrays):
                e = a[common]
                record["mae"][model] = float(np.abs(e).mean()) if count else None
                record["rmse"][model] = float(np.sqrt((e * e).mean())) if count else None
            frames.append(record)
        truth = sum(f["truth_pixels"] for f in frames)
        mean = {"share": sum(f["common_pixels"] for f in frames) / truth if truth else None}
        for metric in ("mae", "rmse"):
            mean[metric] = {}
            for model in models:
                values = [f[metric][model] for f in frames if f[metric][model] is not None]
                mean[metric][model] = sum(values) / len(values) if values else None
        with open(os.path.join(directory, "%s_common.json" % input_name), "w") as f:
            json.dump({"models": models, "frames": frames, "mean_over_frames": mean}, f, indent=1)
            f.write("\n")
    if not keep:
        shutil.rmtree(base)


def load_common(directory, input_name):
    path = os.path.join(directory, "%s_common.json" % input_name)
    return load(path) if os.path.exists(path) else None


def fmt(value, digits):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    return "%.*f" % (digits, value)


def fmt_ms(value):
    if value is None or not math.isfinite(value):
        return "–"
    return "%.1f" % value if value < 10 else "%.0f" % value


class Table:
    def __init__(self, key, title, caption, header):
        self.key, self.title, self.caption, self.header = key, title, caption, header
        self.rows = []  # (cells, record)

    def add(self, cells, record):
        self.rows.append((cells, record))

    def markdown(self):
        lines = ["### %s" % self.title, "", self.caption, ""]
        lines.append("| " + " | ".join(self.header) + " |")
        align = ["---"] + ["---:"] * (len(self.header) - 1)
        lines.append("|" + "|".join(align) + "|")
        for cells, _ in self.rows:
            lines.append("| " + " | ".join(cells) + " |")
        return "\n".join(lines) + "\n"

    def as_json(self):
        return {"title": self.title, "caption": self.caption, "header": self.header,
                "rows": [json_safe(r) for _, r in self.rows]}


DEPTH_HEADER = ["Method", "MAE [m]", "RMSE [m]", "RMSE_log", "AbsRel", "δ<1.25", "Coverage",
                "Median runtime [ms]"]


def depth_cells(name, m, runtime):
    return [name, fmt(m["mae"], 2), fmt(m["rmse"], 2), fmt(m["rmse_log"], 3), fmt(m["abs_rel"], 3),
            fmt(m["delta1"], 3), fmt(100 * m["coverage"], 1) + " %" if math.isfinite(m["coverage"])
            else "–", fmt_ms(runtime)]


def level_of(doc, percent):
    levels, runtime = aggregate(doc["frames"])
    for level in levels:
        if abs(level["retain_percent"] - percent) < 1e-9:
            return level["mean_over_frames"], runtime
    return None, runtime


def failure_reason(text):
    """Short reason for a model that could not run: "needs pose" when the tool asked for one."""
    lower = text.lower()
    if "pose" in lower and ("no such file" in lower or "cannot" in lower or "missing" in lower or
                            "needs" in lower or "required" in lower or "not found" in lower):
        return "needs pose"
    return "failed: " + text.strip()[:120]


def failures_of(directory, prefix):
    """Models whose run of `prefix` failed: {model: reason} from eval.sh's *.line.error files."""
    out = {}
    for model in MODEL_NAMES:
        path = os.path.join(directory, "%s_%s.line.error" % (prefix, model))
        if os.path.exists(path):
            with open(path) as f:
                out[model] = failure_reason(f.read())
    return out


COMMON_HEADER = "MAE, common pixels [m]"


def common_note(common):
    share = common["mean_over_frames"]["share"]
    return (" %s: over the ground-truth pixels that every model of the table predicts (%s of "
            "them; mean over frames), so that a model predicting only near its samples is not "
            "scored on easier pixels than the others." %
            (COMMON_HEADER, "–" if share is None else "%.1f %%" % (100 * share)))


def depth_table(key, title, caption, docs, percent, failures=None, common=None):
    """common: the suite's <input>_common.json (all pixels only): adds its MAE column."""
    header = DEPTH_HEADER + ([COMMON_HEADER] if common else [])
    table = Table(key, title, caption + (common_note(common) if common else ""), header)
    for model, doc in docs:
        m, runtime = level_of(doc, percent)
        if m is None:
            continue
        cells = depth_cells(MODEL_NAMES.get(model, model), m, runtime)
        record = dict(model=model, retain_percent=percent, median_runtime_ms=runtime, **m)
        if common:
            record["mae_common"] = common["mean_over_frames"]["mae"].get(model)
            cells.append(fmt(record["mae_common"], 2))
        table.add(cells, record)
    for model, reason in sorted((failures or {}).items()):
        table.add([MODEL_NAMES.get(model, model), reason] + ["–"] * (len(header) - 2),
                  dict(model=model, retain_percent=percent, error=reason))
    return table


def calibration_rows(model, input_name, doc):
    """Per frame and pooled ('all'): observed coverage at each nominal level, 100 % retention."""
    per_frame = []
    for f in doc["frames"]:
        level = [r for r in f["retention"] if abs(r["retain_percent"] - 100) < 1e-9]
        if level and level[0].get("calibration"):
            per_frame.append(("%05d" % f["frame"], level[0]["calibration"]))
    if not per_frame:
        return []
    levels = [c["level"] for c in per_frame[0][1]]
    inside = [sum(c[i]["inside"] for _, c in per_frame) for i in range(len(levels))]
    count = sum(c[0]["count"] for _, c in per_frame)
    pooled = [{"level": l, "inside": n, "count": count} for l, n in zip(levels, inside)]
    rows = []
    for frame, curve in per_frame + [("all", pooled)]:
        observed = [c["inside"] / c["count"] if c["count"] else float("nan") for c in curve]
        rows.append(([MODEL_NAMES.get(model, model), input_name, frame] +
                     [fmt(100 * o, 1) + " %" if math.isfinite(o) else "–" for o in observed],
                     dict(model=model, input=input_name, frame=frame, levels=levels,
                          observed=observed, count=curve[0]["count"])))
    return rows


NVS_HEADER = ["Preview PSNR [dB]", "SSIM", "PSNR excl. ref. [dB]", "Covered PSNR [dB]",
              "Coverage", "Depth [ms]", "Render [ms]"]
NVS_NOTE = ("Preview PSNR/SSIM: hole-filled preview frames vs the recorded images (the paper's "
            "metric protocol), mean over the 16 frames including the reference view; covered PSNR "
            "and coverage: the raw conditioning frames (the diffusion model fills the holes; it is "
            "not part of this package). Depth: the model's compute time; render: splatting, "
            "metrics and PNG/video output of the 16 frames.")


def nvs_run(prefix, depth_prefix=None):
    """Metrics of one render_conditioning run written by eval.sh (None if it did not run); the
    depth's runtime from depth_prefix's run (default: prefix's)."""
    if not os.path.exists(prefix + ".metrics.json"):
        return None
    metrics = load(prefix + ".metrics.json")
    depth_json = (depth_prefix or prefix) + ".depth.json"
    depth = load(depth_json) if os.path.exists(depth_json) else {}
    render = load(prefix + ".render.json")
    mean, excl = metrics["mean"], metrics["mean_without_reference"]
    return dict(psnr=mean["psnr"], ssim=mean["ssim"], psnr_without_reference=excl["psnr"],
                covered_psnr=mean["covered_psnr"], coverage=mean["coverage"],
                depth_ms=depth.get("compute_ms"), render_ms=render.get("total_ms"),
                gt_frames=len(metrics["frames"]), size=render.get("size"))


def nvs_cells(run):
    return [fmt(run["psnr"], 2), fmt(run["ssim"], 3), fmt(run["psnr_without_reference"], 2),
            fmt(run["covered_psnr"], 2),
            fmt(run["coverage"], 2) if run["coverage"] is not None else "–",
            fmt_ms(run["depth_ms"]) if run["depth_ms"] is not None else "–",
            fmt_ms(run["render_ms"]) if run["render_ms"] is not None else "–"]


def suite_tables(suite, raw, label, truth, notes, lidar_note=""):
    d = os.path.join(raw, suite)
    tables = []

    def docs_of(prefix, models):
        out = []
        for model in models:
            path = os.path.join(d, "%s_%s.json" % (prefix, model))
            if os.path.exists(path):
                out.append((model, load(path)))
        return out

    radar = docs_of("radar", MODEL_NAMES)
    lidar = docs_of("lidar", MODEL_NAMES)
    radar_failures, lidar_failures = failures_of(d, "radar"), failures_of(d, "lidar")
    if radar or radar_failures:
        frames = ", ".join("%05d" % f["frame"] for f in radar[0][1]["frames"]) if radar else "–"
        stride = radar[0][1]["config"].get("stride", 1) if radar else 1
        resolution = "full resolution (stride 1)" if stride == 1 else \
            "stride %d (every %d-th pixel in both directions)" % (stride, stride)
        for percent, which in ((100, "all pixels"), (80, "kept pixels at 80 %")):
            tables.append(depth_table(
                "%s_radar_%d" % (suite, percent),
                "%s: depth from radar, %s" % (label, which),
                "Radar input, frames %s, %s; ground truth: %s. Metrics are "
                "means over frames of the ground-truth pixels that have a %s (Coverage = their "
                "share; kernel and linear predict only near / between samples).%s%s" %
                (frames, resolution, truth, "kept prediction" if percent < 100 else "prediction",
                 RETENTION_NOTE if percent < 100 else "", notes),
                radar, percent, radar_failures,
                load_common(d, "radar") if percent == 100 else None))
    if lidar or lidar_failures:
        cfg = lidar[0][1]["config"] if lidar else {"subsample": 4, "stride": 4}
        k, stride = cfg["subsample"], cfg["stride"]
        frames = ", ".join("%05d" % f["frame"] for f in lidar[0][1]["frames"]) if lidar else "–"
        gt = "the other %d of every %d LiDAR returns, projected (nearest return per pixel)" % (
            k - 1, k)
        for percent, which in ((100, "all pixels"), (80, "kept pixels at 80 %")):
            tables.append(depth_table(
                "%s_lidar_%d" % (suite, percent),
                "%s: depth from LiDAR (1 in %d returns), %s" % (label, k, which),
                "Input: every %d-th LiDAR return (phase 0); ground truth: %s. Frames %s, stride %d "
                "(every %d-th pixel in both directions). The local GP runs with the documented "
                "tile approximation (--max-neighbors 64): the exact GP needs about a minute per "
                "frame on this input. Its RMSE_log is dominated by a few tenths of a percent of "
                "pixels where the GP posterior mean overshoots to a depth <= 0 near dense "
                "close-range returns (clipped to 1 mm; the exact GP does the same). ground_gp "
                "chooses its sparse or dense input mode itself (ground_input auto).%s%s%s" %
                (k, gt, frames, stride, stride, lidar_note,
                 RETENTION_NOTE if percent < 100 else "", notes),
                lidar, percent, lidar_failures,
                load_common(d, "lidar") if percent == 100 else None))
    # Calibration curves of the predictive variance (all pixels): the radar default (image_guided),
    # ground_gp and, for contrast, the reference GP on radar; ground_gp (the LiDAR default) on LiDAR
    # input too.
    rows = []
    for input_name, docs, models in (("radar", radar, ("image_guided", "ground_gp", "local_gp_mle")),
                                     ("LiDAR 1-in-4", lidar, ("ground_gp",))):
        for model, doc in docs:
            if model in models:
                rows += calibration_rows(model, input_name, doc)
    if rows:
        levels = rows[0][1]["levels"]
        header = ["Method", "Input", "Frame"] + ["%g %%" % (100 * l) for l in levels]
        table = Table("%s_calibration" % suite, "%s: calibration of the variance" % label,
                      "Observed share of the ground-truth pixels (all pixels, 100 %% retention) "
                      "inside the central Gaussian interval mean ± z·σ of each nominal coverage "
                      "(σ² = the predicted variance; 95 %% is ±1.96σ). Calibrated: observed "
                      "≈ nominal; above: variance too large, below: too small. 'all' pools the "
                      "frames' pixels. Ground truth: %s.%s" % (truth, notes), header)
        for cells, record in rows:
            table.add(cells, record)
        tables.append(table)
    # Radius ablation: r = 2 is the radar run.
    radius_docs = []
    for radius in (1, 2, 4):
        path = os.path.join(d, "radius_%d.json" % radius) if radius != 2 else \
            os.path.join(d, "radar_local_gp_mle.json")
        if os.path.exists(path):
            radius_docs.append((radius, load(path)))
    if radius_docs:
        header = ["Radius", "MAE [m]", "RMSE [m]", "RMSE_log", "AbsRel", "δ<1.25",
                  "MAE kept 80 % [m]", "Median runtime [ms]"]
        table = Table("%s_radius" % suite, "%s: radius ablation (local GP, radar)" % label,
                      "Neighbourhood radius of the local GP; all pixels, and MAE over the kept "
                      "pixels at 80 %% retention. Paper (9 VoD videos): MAE 10.88 / 10.67 / "
                      "10.94 m for r = 1 / 2 / 4 deg.%s" % notes, header)
        for radius, doc in radius_docs:
            m, runtime = level_of(doc, 100)
            m80, _ = level_of(doc, 80)
            table.add(["%d°" % radius, fmt(m["mae"], 2), fmt(m["rmse"], 2), fmt(m["rmse_log"], 3),
                       fmt(m["abs_rel"], 3), fmt(m["delta1"], 3),
                       fmt(m80["mae"], 2) if m80 else "–", fmt_ms(runtime)],
                      dict(radius_deg=radius, median_runtime_ms=runtime,
                           mae_kept80=(m80 or {}).get("mae"), **m))
        tables.append(table)
    # Retention ablation: every model, from the radar runs (one run, four retention levels).
    if radar:
        header = ["Retention"] + [MODEL_NAMES[m] + " MAE [m]" for m, _ in radar] + \
                 ["Local GP RMSE_log", "Local GP coverage"]
        table = Table("%s_retention" % suite, "%s: retention ablation (radar)" % label,
                      "MAE over the ground-truth pixels that are kept when each model keeps the "
                      "given share of all pixels with the lowest variance (100 %%: every "
                      "prediction). The paper finds 80 %% best for the local GP.%s%s" %
                      (RETENTION_NOTE, notes), header)
        gp = dict(radar).get("local_gp_mle")
        for percent in (40, 60, 80, 100):
            cells, record = ["%d %%" % percent], {"retain_percent": percent}
            for model, doc in radar:
                m, _ = level_of(doc, percent)
                cells.append(fmt(m["mae"], 2) if m else "–")
                record[model + "_mae"] = m["mae"] if m else None
            mg = level_of(gp, percent)[0] if gp else None
            cells += [fmt(mg["rmse_log"], 3) if mg else "–",
                      fmt(100 * mg["coverage"], 1) + " %" if mg else "–"]
            table.add(cells, record)
        tables.append(table)
    # Novel view (no exact depth on real data, so no oracle row here).
    nvs_dir = os.path.join(d, "nvs")

    def radar_nvs_rows(suffix):
        """(cells, record) per model and retention of the renders PREFIX + suffix."""
        found = []
        for model in MODEL_NAMES:
            for percent in (40, 60, 80, 100):
                prefix = os.path.join(nvs_dir, "radar_%s_%d" % (model, percent))
                run = nvs_run(prefix + suffix, prefix)
                if run is not None:
                    found.append(([MODEL_NAMES[model], "%d %%" % percent] + nvs_cells(run),
                                  dict(model=model, retain_percent=percent, **run)))
        return found

    rows = radar_nvs_rows("")
    size = next((r["size"] for _, r in reversed(rows) if r["size"]), None)
    # The same depths along the odometry poses (eval.sh renders VoD along both).
    odom_rows = radar_nvs_rows(".odomToCamera")
    if rows:
        reference = "08350, trajectory 08350–08365" if suite == "vod" else "00000"
        table = Table("%s_nvs" % suite, "%s: novel view from radar depth" % label,
                      "Reference image %s (16 recorded poses = ground truth). Depth from radar at "
                      "the given retention, rendered with GEN3C's splatting at %s (H x W) into the "
                      "16 recorded poses only: GEN3C's 121-frame trajectory puts them at frames 0, "
                      "8, ..., 120, so the metrics equal those of the full render (checked on VoD, "
                      "local GP at 80 %%: 13.4611 dB both ways) at 1/7 of the cost. %s No oracle "
                      "row: real data has no exact depth.%s" %
                      (reference, "x".join(str(v) for v in size or []), NVS_NOTE, notes),
                      ["Depth", "Retention"] + NVS_HEADER)
        for cells, record in rows:
            table.add(cells, record)
        tables.append(table)
    if odom_rows:
        table = Table("%s_nvs_odometry" % suite,
                      "%s: novel view from radar depth, odometry trajectory" % label,
                      "The table above with the recorded poses read from the pose files' "
                      "odomToCamera instead of mapToCamera (the reference renderer's). The map "
                      "poses carry the localisation's corrections: on 08350–08365 their rotation "
                      "since 08350 differs from the odometry's by 0.04–0.53 deg, jumping between "
                      "neighbouring frames (0.09, 0.52, 0.09 deg at 08363–08365; 0.53 deg is about "
                      "9 pixels at 704x1280), and their translation by up to 0.18 m (REP 105: the "
                      "odom frame is continuous, the map frame may jump). The recorded images are "
                      "the judge of which is the camera's motion.",
                      ["Depth", "Retention"] + NVS_HEADER)
        for cells, record in odom_rows:
            table.add(cells, record)
        tables.append(table)
    return tables


# ---------------------------------------------------------------------------------------------
# synthetic scenes (eval/synthetic_scenes.tsv)

SCENE_LIST = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "eval",
                          "synthetic_scenes.tsv")
SPLITS = ("validation", "dev")
INPUTS = (("radar", "radar"), ("lidar", "LiDAR"))


def scene_order():
    """Scene names in the order of eval/synthetic_scenes.tsv."""
    order = []
    if os.path.exists(SCENE_LIST):
        with open(SCENE_LIST) as f:
            for line in f:
                if line.strip() and not line.startswith("#"):
                    order.append(line.split("\t")[0])
    return order


def scene_results(directory):
    """Everything measured on one scene: depth (per input, model) and novel views."""
    info = load(os.path.join(directory, "scene.json"))
    out = dict(info, depth={}, nvs={}, errors={}, retention={})
    for input_name, _ in INPUTS:
        for model in MODEL_NAMES:
            path = os.path.join(directory, "%s_%s.json" % (input_name, model))
            if os.path.exists(path):
                doc = load(path)
                all_px, runtime = level_of(doc, 100)
                kept, _ = level_of(doc, 80)
                out["depth"][(input_name, model)] = dict(
                    mae=all_px["mae"] if all_px else None,
                    depth_coverage=all_px["coverage"] if all_px else None,
                    mae_kept80=kept["mae"] if kept else None, runtime_ms=runtime,
                    frames=[f["frame"] for f in doc["frames"]])
        out["errors"].update({(input_name, m): r for m, r in
                              failures_of(directory, input_name).items()})
        common = load_common(directory, input_name)
        if common:
            for model, mae in common["mean_over_frames"]["mae"].items():
                if (input_name, model) in out["depth"]:
                    out["depth"][(input_name, model)]["mae_common"] = mae
            out.setdefault("common_share", {})[input_name] = common["mean_over_frames"]["share"]
    nvs_dir = os.path.join(directory, "nvs")
    if os.path.isdir(nvs_dir):
        for kind in ("oracle", "exact_nosky"):
            run = nvs_run(os.path.join(nvs_dir, kind))
            if run:
                out["nvs"][kind] = run
        for name in sorted(os.listdir(nvs_dir)):
            if not name.endswith(".metrics.json"):
                continue
            stem = name[:-len(".metrics.json")]
            parts = stem.split("_")
            if parts[0] not in dict(INPUTS) or not parts[-1].isdigit():
                continue
            model = "_".join(parts[1:-1])
            out["retention"][parts[0]] = int(parts[-1])
            run = nvs_run(os.path.join(nvs_dir, stem))
            oracle = out["nvs"].get("oracle")
            if oracle and run["covered_psnr"] is not None and oracle["covered_psnr"] is not None:
                run["gap_db"] = run["covered_psnr"] - oracle["covered_psnr"]
            out["nvs"][(parts[0], model)] = run
    return out


def mean_of(values):
    values = [v for v in values if v is not None and math.isfinite(v)]
    return (sum(values) / len(values), len(values)) if values else (float("nan"), 0)


def synthetic_tables(raw, lidar_note=""):
    root = os.path.join(raw, "synthetic")
    order = scene_order()
    names = [n for n in os.listdir(root) if os.path.exists(os.path.join(root, n, "scene.json"))]
    names.sort(key=lambda n: (order.index(n) if n in order else len(order), n))
    scenes = [scene_results(os.path.join(root, n)) for n in names]
    if not scenes:
        return []
    models = [m for m in MODEL_NAMES if any(
        (i, m) in s["nvs"] or (i, m) in s["depth"] for s in scenes for i, _ in INPUTS)]
    # Novel-view retention per input (each config's own, e.g. radar 100 %, LiDAR 80 %).
    retention_of = {}
    for s in scenes:
        for input_name, percent in s["retention"].items():
            retention_of.setdefault(input_name, percent)
    if len(set(retention_of.values())) == 1:
        retention = "%d %%" % next(iter(retention_of.values()))
    elif retention_of:
        retention = ", ".join("%s %d %%" % (label, retention_of[name])
                              for name, label in INPUTS if name in retention_of)
    else:
        retention = "–"
    first = scenes[0]
    depth_frames = next((", ".join(str(f) for f in d["frames"]) for s in scenes
                         for d in s["depth"].values()), "–")
    setup = ("Scenes of eval/synthetic_scenes.tsv made by make_synthetic_scene --num-frames %s "
             "--scale %s plus each scene's arguments. Novel views: frame 0's depth (radar; or all "
             "LiDAR returns) at %s retention, rendered with GEN3C's splatting at 352x640 into "
             "the 16 recorded poses; the oracle renders the exact depth with the sky at GEN3C's "
             "100 m clamp, 'exact, sky dropped' the exact depth without the sky; gap = covered "
             "PSNR minus the oracle's. Depth: against the exact depth at frame(s) %s (radar: all "
             "returns, stride 1; LiDAR: 1 in 4 returns as input, stride 4). On LiDAR input the "
             "local GP uses the tile approximation (--max-neighbors 64), and kernel regression on "
             "all LiDAR returns (the novel views) a 1° radius.%s" %
             (first.get("frames"), first.get("scale"), retention,
              depth_frames, lidar_note))
    extra_path = os.path.join(root, "scene_args.txt")
    if os.path.exists(extra_path):
        with open(extra_path) as f:
            setup += " Every scene also made with `%s` (EVAL_SCENE_ARGS)." % f.read().strip()
    tables = []

    def split_mean(split, key, field):
        return mean_of([s["nvs"].get(key, {}).get(field) for s in scenes if s["split"] == split])

    def depth_mean(split, key, field):
        return mean_of([s["depth"].get(key, {}).get(field) for s in scenes
                        if s["split"] == split])

    # Summary per split: validation (report) first, then dev (tuning).
    for split in SPLITS:
        count = sum(1 for s in scenes if s["split"] == split)
        if count == 0:
            continue
        header = ["Input", "Depth", "Covered PSNR [dB]", "Gap to oracle [dB]", "Coverage",
                  "Preview PSNR [dB]", "MAE [m]", "Depth coverage", "MAE kept 80 % [m]",
                  "Depth runtime [ms]"]
        table = Table("synthetic_%s_mean" % split,
                      "Synthetic scenes: %s mean (%d scenes)" % (split, count),
                      "Means over the %d %s scenes of each column. Depth coverage: share of "
                      "the exact-depth pixels that have a prediction (kernel and linear predict "
                      "only near / between returns, so their MAE covers fewer pixels). %s %s" %
                      (count, split, setup, NVS_NOTE), header)
        for kind, label in (("oracle", "exact depth, sky at 100 m (oracle)"),
                            ("exact_nosky", "exact depth, sky dropped")):
            cov, n = split_mean(split, kind, "covered_psnr")
            if n:
                table.add(["–", label, fmt(cov, 2), fmt(0.0, 2) if kind == "oracle" else
                           fmt(cov - split_mean(split, "oracle", "covered_psnr")[0], 2),
                           fmt(split_mean(split, kind, "coverage")[0], 2),
                           fmt(split_mean(split, kind, "psnr")[0], 2), "0", "1.00", "0", "–"],
                          dict(depth=kind, split=split, scenes=n, covered_psnr=cov,
                               coverage=split_mean(split, kind, "coverage")[0],
                               psnr=split_mean(split, kind, "psnr")[0]))
        for input_name, input_label in INPUTS:
            for model in models:
                key = (input_name, model)
                cov, n = split_mean(split, key, "covered_psnr")
                mae, nd = depth_mean(split, key, "mae")
                if n == 0 and nd == 0:
                    continue
                record = dict(input=input_name, model=model, split=split, scenes=n,
                              covered_psnr=cov, gap_db=split_mean(split, key, "gap_db")[0],
                              coverage=split_mean(split, key, "coverage")[0],
                              psnr=split_mean(split, key, "psnr")[0], mae=mae,
                              mae_kept80=depth_mean(split, key, "mae_kept80")[0],
                              depth_coverage=depth_mean(split, key, "depth_coverage")[0],
                              runtime_ms=depth_mean(split, key, "runtime_ms")[0])
                partial = " (%d of %d scenes)" % (n, count) if 0 < n < count else ""
                table.add([input_label, MODEL_NAMES[model], fmt(cov, 2) + partial,
                           fmt(record["gap_db"], 2), fmt(record["coverage"], 2),
                           fmt(record["psnr"], 2), fmt(mae, 2),
                           fmt(record["depth_coverage"], 2), fmt(record["mae_kept80"], 2),
                           fmt_ms(record["runtime_ms"])], record)
        tables.append(table)

    # Per scene and input: novel view (covered PSNR, gap, coverage) and preview PSNR / depth MAE.
    for input_name, input_label in INPUTS:
        keys = [(input_name, m) for m in models
                if any((input_name, m) in s["nvs"] or (input_name, m) in s["depth"] or
                       (input_name, m) in s["errors"] for s in scenes)]
        if not keys:
            continue
        nvs_keys = [k for k in keys if any(k in s["nvs"] for s in scenes)]
        nvs_header = ["Scene", "Split", "Oracle", "Exact, sky dropped"] + \
            [MODEL_NAMES[m] for _, m in nvs_keys]
        nvs_table = Table("synthetic_%s_nvs_per_scene" % input_name,
                          "Synthetic scenes, %s input: novel view per scene" % input_label,
                          "Cell: covered PSNR [dB] (gap to the oracle) / coverage. %s" % setup,
                          nvs_header)
        other_header = ["Scene", "Split"] + [MODEL_NAMES[m] for _, m in keys]
        other_table = Table("synthetic_%s_preview_depth_per_scene" % input_name,
                            "Synthetic scenes, %s input: preview PSNR and depth MAE per scene" %
                            input_label,
                            "Cell: preview PSNR [dB] (hole-filled frames, 16 poses) / depth MAE "
                            "[m] (all pixels). %s" % setup, other_header)

        def nvs_cell(run, gap=True):
            if not run:
                return "–"
            text = fmt(run["covered_psnr"], 2)
            if gap and run.get("gap_db") is not None:
                text += " (%+.2f)" % run["gap_db"]
            return text + " / " + fmt(run["coverage"], 2)

        for s in scenes:
            cells = [s["name"], s["split"], nvs_cell(s["nvs"].get("oracle"), False),
                     nvs_cell(s["nvs"].get("exact_nosky"), False)]
            other = [s["name"], s["split"]]
            for key in nvs_keys:
                cells.append(nvs_cell(s["nvs"].get(key)))
            for key in keys:
                if key in s["errors"] and key not in s["depth"]:
                    other.append(s["errors"][key])
                    continue
                run = s["nvs"].get(key)
                depth = s["depth"].get(key, {})
                other.append("%s / %s" % (fmt(run["psnr"], 2) if run else "–",
                                          fmt(depth.get("mae"), 2)))
            record = dict(scene=s["name"], split=s["split"], args=s.get("args"),
                          oracle=s["nvs"].get("oracle"), exact_nosky=s["nvs"].get("exact_nosky"),
                          models={m: dict(nvs=s["nvs"].get(k), depth=s["depth"].get(k),
                                          error=s["errors"].get(k)) for k in keys
                                  for m in [k[1]]})
            nvs_table.add(cells, record)
            other_table.add(other, dict(scene=s["name"], split=s["split"]))
        for split in SPLITS:
            if not any(s["split"] == split for s in scenes):
                continue
            cells = ["**%s mean**" % split, split]
            for kind in ("oracle", "exact_nosky"):
                cov, n = split_mean(split, kind, "covered_psnr")
                cells.append("%s / %s" % (fmt(cov, 2), fmt(split_mean(split, kind,
                                                                       "coverage")[0], 2))
                             if n else "–")
            other = ["**%s mean**" % split, split]
            record = dict(scene="%s mean" % split, split=split, models={})
            for key in keys:
                cov, n = split_mean(split, key, "covered_psnr")
                gap = split_mean(split, key, "gap_db")[0]
                coverage = split_mean(split, key, "coverage")[0]
                psnr = split_mean(split, key, "psnr")[0]
                mae = depth_mean(split, key, "mae")[0]
                if key in nvs_keys:
                    cells.append("%s (%+.2f) / %s" % (fmt(cov, 2), gap, fmt(coverage, 2))
                                 if n and math.isfinite(gap) else
                                 ("%s / %s" % (fmt(cov, 2), fmt(coverage, 2)) if n else "–"))
                other.append("%s / %s" % (fmt(psnr, 2), fmt(mae, 2)))
                record["models"][key[1]] = dict(covered_psnr=cov, gap_db=gap, coverage=coverage,
                                                psnr=psnr, mae=mae, scenes=n)
            nvs_table.add(cells, record)
            other_table.add(other, record)
        tables += [nvs_table, other_table]
        common_table = synthetic_common_table(scenes, input_name, input_label, keys, setup)
        if common_table:
            tables.append(common_table)
    return tables


def synthetic_common_table(scenes, input_name, input_label, keys, setup):
    """Per scene: each model's depth MAE over the pixels every model predicts, and their share."""
    with_common = [s for s in scenes if input_name in s.get("common_share", {})]
    if not with_common:
        return None
    keys = [k for k in keys if any("mae_common" in s["depth"].get(k, {}) for s in with_common)]
    table = Table("synthetic_%s_depth_common_per_scene" % input_name,
                  "Synthetic scenes, %s input: depth MAE on the pixels every model predicts" %
                  input_label,
                  "Cell: depth MAE [m] over the exact-depth pixels that every model of the row "
                  "predicts (the depth runs of the tables above; kernel and linear predict only "
                  "near / between returns, so their own MAE covers easier pixels); Common: the "
                  "share of the exact-depth pixels that are. %s" % setup,
                  ["Scene", "Split", "Common"] + [MODEL_NAMES[m] for _, m in keys])
    for s in with_common:
        table.add([s["name"], s["split"], fmt(s["common_share"][input_name], 2)] +
                  [fmt(s["depth"].get(k, {}).get("mae_common"), 2) for k in keys],
                  dict(scene=s["name"], split=s["split"], share=s["common_share"][input_name],
                       mae_common={k[1]: s["depth"].get(k, {}).get("mae_common") for k in keys}))
    for split in SPLITS:
        in_split = [s for s in with_common if s["split"] == split]
        if not in_split:
            continue
        share = mean_of([s["common_share"][input_name] for s in in_split])[0]
        means = {k[1]: mean_of([s["depth"].get(k, {}).get("mae_common") for s in in_split])[0]
                 for k in keys}
        table.add(["**%s mean**" % split, split, fmt(share, 2)] +
                  [fmt(means[k[1]], 2) for k in keys],
                  dict(scene="%s mean" % split, split=split, share=share, mae_common=means))
    return table


def lidar_ground_gp_note(args):
    """The captions' sentence on ground_gp's own arguments on 1-in-4 LiDAR input (eval.sh's)."""
    if not args:
        return ""
    return (" ground_gp on LiDAR input runs with %s, as config/lidar.yaml does (the returns the "
            "camera cannot see left out; lidar.yaml's sky only in the novel views)." % args)


def tables(out_dir, seconds, threads, split="all", lidar_ground_gp_args=""):
    lidar_note = lidar_ground_gp_note(lidar_ground_gp_args)
    raw = os.path.join(out_dir, "raw")
    if not os.path.isdir(raw):
        fail("%s: no raw results (run scripts/eval.sh first)" % raw)
    all_tables = []
    if os.path.isdir(os.path.join(raw, "vod")):
        all_tables += suite_tables("vod", raw, "View-of-Delft",
                                   "the LiDAR scan projected into the image (nearest return per "
                                   "pixel)", "", lidar_note)
    if os.path.isdir(os.path.join(raw, "synthetic")):
        all_tables = synthetic_tables(raw, lidar_note) + all_tables
    lidar_truth = "the LiDAR scan projected into the image (nearest return per pixel)"
    for suite, label, note in (
            ("astyx", "Astyx HiRes (4D radar, VLP-16)",
             " Astyx's VLP-16 is sparse and its returns can sit metres from the radar's on the "
             "same object: a second opinion next to VoD's."),
            ("nuscenes", "nuScenes (sparse radar, 32-beam LiDAR)", ""),
            ("kitti", "KITTI object (HDL-64)", ""),
            ("distorted_camera", "Distorted camera (LiDAR, plumb_bob lens)",
             " The camera has lens distortion (camera_info D); see the data README.")):
        if os.path.isdir(os.path.join(raw, suite)):
            all_tables += suite_tables(suite, raw, label, lidar_truth, note, lidar_note)
    if not all_tables:
        fail("%s: no table could be built" % raw)
    when = time.strftime("%Y-%m-%d %H:%M", time.localtime())
    head = ("Measured by `make eval` (scripts/eval.sh) on %s, %s cores%s; synthetic scenes: "
            "%s. Runtimes are medians over frames of the model's compute time "
            "(DepthCompleter::complete: angles, model, retention) unless stated otherwise.\n" %
            (when, threads, ", whole run %.0f s" % seconds if seconds else "",
             "all" if split == "all" else "the %s split only" % split))
    text = "## Evaluation tables\n\n" + head + "\n" + "\n".join(t.markdown() for t in all_tables)
    with open(os.path.join(out_dir, "tables.md"), "w") as f:
        f.write(text)
    with open(os.path.join(out_dir, "tables.json"), "w") as f:
        json.dump({"generated": when, "seconds": seconds, "threads": threads, "split": split,
                   "tables": {t.key: t.as_json() for t in all_tables}}, f, indent=1)
        f.write("\n")
    sys.stdout.write(text)


def main(argv):
    if len(argv) >= 2 and argv[1] == "merge":
        if len(argv) < 4:
            fail("usage: eval_tables.py merge MERGED.json SHARD.json [SHARD.json ...]")
        merge(argv[2], argv[3:])
        return
    if len(argv) >= 3 and argv[1] == "common":
        if argv[3:] not in ([], ["--keep"]):
            fail("usage: eval_tables.py common DIR [--keep]")
        common_errors(argv[2], keep=argv[3:] == ["--keep"])
        return
    if len(argv) >= 3 and argv[1] == "tables":
        seconds, threads, split, lidar_ground_gp_args = None, "?", "all", ""
        rest = argv[3:]
        while rest:
            if rest[0] == "--seconds" and len(rest) > 1:
                seconds = float(rest[1])
            elif rest[0] == "--threads" and len(rest) > 1:
                threads = rest[1]
            elif rest[0] == "--split" and len(rest) > 1:
                split = rest[1]
            elif rest[0] == "--lidar-ground-gp-args" and len(rest) > 1:
                lidar_ground_gp_args = rest[1]
            else:
                fail("unknown argument '%s'" % rest[0])
            rest = rest[2:]
        tables(argv[2], seconds, threads, split, lidar_ground_gp_args)
        return
    sys.stderr.write(__doc__)
    sys.exit(2)


if __name__ == "__main__":
    main(sys.argv)
