// evaluate_depth: depth accuracy of a completion model (or of saved complete_depth output) on
// View-of-Delft-layout frames — MAE, RMSE, RMSE_log, AbsRel and delta<1.25 over the ground-truth
// pixels, per frame and aggregated, at several retention levels from one completion run. Ground
// truth: the LiDAR scan projected into the image (nearest return per pixel), or the exact depth
// image ROOT/depth_gt/NNNNN.npy of the synthetic scene. `--shard i/N` evaluates every N-th frame
// so that a scheduler can spread a dataset over machines; the JSON keeps the raw sums, so shards
// merge exactly (scripts/eval_tables.py merge).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "common/cli.hpp"
#include "common/depth_options.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/retention.hpp"
#include "multimodal_nvs/core/eval/depth_metrics.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace mm = multimodal_nvs;

namespace {

void declareOptions(mm::cli::Args& args) {
  mm::cli::declareDepthModelOptions(args);
  args.option("vod-root", 1, "View-of-Delft layout root (real VoD or make_synthetic_scene output)");
  args.option("frames", 1, "frames: numbers and ranges, e.g. 549,1047 or 8350-8365");
  args.option("frames-file", 1, "file with one frame number per line (instead of --frames)");
  args.option("shard", 1, "i/N: evaluate only frames with list index % N == i", "0/1");
  args.option("input", 1, "radar|lidar: the sensor completed from", "radar");
  args.option("subsample", 1,
              "use every k-th input return (1-in-k); with LiDAR input and LiDAR "
              "ground truth the other returns become the ground truth",
              "1");
  args.option("subsample-phase", 1, "which return of each k starts the input subsample", "0");
  args.option("gt", 1,
              "auto|lidar|dense: ground truth (auto: ROOT/depth_gt/NNNNN.npy when it "
              "exists, else the LiDAR scan)",
              "auto");
  args.option("pred", 1,
              "evaluate saved output PREFIX_depth.npy (+ PREFIX_variance.npy for "
              "retention) of one frame instead of running a model");
  args.option("stride", 1, "grid step in pixels (as complete_depth --stride)", "1");
  args.option("retain-percent", 1,
              "comma list: keep p% of all grid pixels with the lowest "
              "variance, evaluated on the kept pixels (100: every prediction)",
              "100");
  args.option("calibration-levels", 1,
              "comma list of nominal coverages (percent, in (0, 100)) of the central Gaussian "
              "intervals mean +- z sigma whose observed coverage is reported",
              "50,68,80,90,95,99");
  args.option("max-depth", 1, "range cap: ignore ground truth deeper than this (0: none)", "0");
  args.option("image-size", 2, "image size H W (default: from the frame's image)");
  args.option("repeat", 1, "run the model N times per frame and report the median time", "1");
  args.option("label", 1, "name of this configuration in the JSON (default: the model)");
  args.option("output", 1, "write the full JSON (per frame and aggregate) to this file");
}

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s << std::setprecision(10) << v;
  return s.str();
}

std::vector<int> parseFrameList(const std::string& text) {
  std::vector<int> frames;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t\r") + 1);
    if (item.empty()) continue;
    const std::size_t dash = item.find('-', 1);
    if (dash == std::string::npos) {
      frames.push_back(mm::io::parseFrameNumber(item));
      continue;
    }
    const int a = mm::io::parseFrameNumber(item.substr(0, dash));
    const int b = mm::io::parseFrameNumber(item.substr(dash + 1));
    if (b < a) throw mm::cli::UsageError("--frames: range '" + item + "' needs A <= B");
    for (int f = a; f <= b; ++f)
      frames.push_back(f);
  }
  if (frames.empty()) throw mm::cli::UsageError("--frames: no frame in '" + text + "'");
  return frames;
}

std::vector<int> framesFrom(const mm::cli::Args& args) {
  if (args.has("frames") == args.has("frames-file")) {
    throw mm::cli::UsageError("give exactly one of --frames LIST or --frames-file FILE");
  }
  if (args.has("frames")) return parseFrameList(args.str("frames"));
  const std::string path = args.str("frames-file");
  std::ifstream in(path);
  if (!in) throw mm::InputError(path + ": cannot open frame list");
  std::string line, joined;
  while (std::getline(in, line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    if (line.find_first_not_of(" \t\r") != std::string::npos) joined += line + ",";
  }
  if (joined.empty()) throw mm::InputError(path + ": no frame numbers");
  return parseFrameList(joined);
}

struct Shard {
  int index = 0, count = 1;
};

Shard parseShard(const std::string& text) {
  Shard s;
  const std::size_t slash = text.find('/');
  char* end = nullptr;
  bool ok = slash != std::string::npos;
  if (ok) {
    const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
    s.index = static_cast<int>(std::strtol(a.c_str(), &end, 10));
    ok = !a.empty() && *end == '\0';
    s.count = static_cast<int>(std::strtol(b.c_str(), &end, 10));
    ok = ok && !b.empty() && *end == '\0';
  }
  if (!ok || s.count < 1 || s.index < 0 || s.index >= s.count) {
    throw mm::cli::UsageError("--shard must be i/N with 0 <= i < N, got '" + text + "'");
  }
  return s;
}

/// Comma list of percentages for `option`; open = exclude 0 and 100.
std::vector<double> parsePercentList(const std::string& option, const std::string& text,
                                     bool open) {
  std::vector<double> out;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    const bool ok = open ? v > 0.0 && v < 100.0 : v >= 0.0 && v <= 100.0;
    if (item.empty() || *end != '\0' || !ok) {
      throw mm::cli::UsageError("--" + option + ": '" + item + "' is not a percentage in " +
                                (open ? "(0, 100)" : "[0, 100]"));
    }
    out.push_back(v);
  }
  if (out.empty()) throw mm::cli::UsageError("--" + option + ": empty list");
  return out;
}

/// Every k-th record starting at `phase` (keep = true) or all the others (keep = false).
std::vector<Eigen::Vector3f> subsample(const std::vector<Eigen::Vector3f>& points, int k, int phase,
                                       bool keep) {
  if (k <= 1) return keep ? points : std::vector<Eigen::Vector3f>();
  std::vector<Eigen::Vector3f> out;
  out.reserve(keep ? points.size() / k + 1 : points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if ((static_cast<int>(i % k) == phase) == keep) out.push_back(points[i]);
  }
  return out;
}

mm::ImageSize imageSizeOf(const mm::cli::Args& args, const mm::io::VodFrame& frame) {
  if (args.has("image-size")) {
    const auto& hw = args.list("image-size");
    const mm::ImageSize size{std::atoi(hw[0].c_str()), std::atoi(hw[1].c_str())};
    if (size.height <= 0 || size.width <= 0) {
      throw mm::cli::UsageError("--image-size must be positive");
    }
    return size;
  }
  const std::string path = frame.image();
  if (!mm::io::fileExists(path)) {
    throw mm::InputError(path + ": image not found (give --image-size H W)");
  }
  const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw mm::InputError(path + ": cannot read or decode image");
  return {image.rows, image.cols};
}

std::string denseTruthPath(const std::string& root, const mm::io::VodFrame& frame) {
  return root + "/depth_gt/" + frame.id() + ".npy";
}

/// Reads a 2-D .npy into row-major floats.
std::vector<float> readImageNpy(const std::string& path, int* rows, int* cols) {
  const mm::io::NpyArray array = mm::io::readNpy(path);
  if (array.shape.size() != 2 || array.shape[0] == 0 || array.shape[1] == 0) {
    throw mm::InputError(path + ": expected a 2-D array (H x W)");
  }
  *rows = static_cast<int>(array.shape[0]);
  *cols = static_cast<int>(array.shape[1]);
  return array.asFloat();
}

struct RetentionResult {
  double percent = 100.0;
  long long kept = 0;
  mm::DepthErrorSums sums;
  mm::CalibrationCounts calibration;
};

struct FrameResult {
  int frame = 0;
  std::string gt_kind;
  std::size_t input_points = 0, input_in_view = 0, gt_points = 0;
  double runtime_ms = std::numeric_limits<double>::quiet_NaN();
  std::string ground_source, ground_mode;  // ground_gp: its plane's source and its mode
  std::vector<RetentionResult> retention;
};

std::string sumsJson(const mm::DepthErrorSums& s) {
  std::ostringstream o;
  o << "{\"gt_pixels\": " << s.gt_pixels << ", \"count\": " << s.count
    << ", \"abs_error\": " << num(s.abs_error) << ", \"sq_error\": " << num(s.sq_error)
    << ", \"sq_log_error\": " << num(s.sq_log_error) << ", \"abs_rel\": " << num(s.abs_rel)
    << ", \"delta1\": " << s.delta1 << "}";
  return o.str();
}

/// [{"level": p, "observed": share, "inside": count}, ...] of the central intervals.
std::string calibrationJson(const mm::CalibrationCounts& c) {
  std::ostringstream o;
  o << "[";
  for (std::size_t i = 0; i < c.levels.size(); ++i) {
    o << (i ? ", " : "") << "{\"level\": " << num(c.levels[i])
      << ", \"observed\": " << num(c.observed(i)) << ", \"inside\": " << c.inside[i]
      << ", \"count\": " << c.count << "}";
  }
  o << "]";
  return o.str();
}

std::string metricsJson(const mm::DepthMetrics& m) {
  std::ostringstream o;
  o << "{\"count\": " << m.count << ", \"gt_pixels\": " << m.gt_pixels
    << ", \"mae\": " << num(m.mae) << ", \"rmse\": " << num(m.rmse)
    << ", \"rmse_log\": " << num(m.rmse_log) << ", \"abs_rel\": " << num(m.abs_rel)
    << ", \"delta1\": " << num(m.delta1) << ", \"coverage\": " << num(m.coverage) << "}";
  return o.str();
}

/// Mean over frames of each metric (frames where it is undefined are skipped).
std::string meanOverFramesJson(const std::vector<FrameResult>& frames, std::size_t level) {
  double sum[6] = {0, 0, 0, 0, 0, 0};
  int count[6] = {0, 0, 0, 0, 0, 0};
  for (const FrameResult& f : frames) {
    const mm::DepthMetrics m = mm::DepthMetrics::from(f.retention[level].sums);
    const double v[6] = {m.mae, m.rmse, m.rmse_log, m.abs_rel, m.delta1, m.coverage};
    for (int i = 0; i < 6; ++i) {
      if (std::isfinite(v[i])) {
        sum[i] += v[i];
        ++count[i];
      }
    }
  }
  auto mean = [&](int i) {
    return count[i] > 0 ? sum[i] / count[i] : std::numeric_limits<double>::quiet_NaN();
  };
  std::ostringstream o;
  o << "{\"frames\": " << frames.size() << ", \"mae\": " << num(mean(0))
    << ", \"rmse\": " << num(mean(1)) << ", \"rmse_log\": " << num(mean(2))
    << ", \"abs_rel\": " << num(mean(3)) << ", \"delta1\": " << num(mean(4))
    << ", \"coverage\": " << num(mean(5)) << "}";
  return o.str();
}

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t mid = v.size() / 2;
  return v.size() % 2 ? v[mid] : 0.5 * (v[mid - 1] + v[mid]);
}

int run(int argc, char** argv) {
  mm::cli::Args args("evaluate_depth",
                     "Depth accuracy (MAE, RMSE, RMSE_log, AbsRel, delta<1.25) of a completion "
                     "model against projected LiDAR or exact depth, per frame and aggregated.");
  declareOptions(args);
  if (!args.parse(argc, argv)) return 0;
  if (!args.has("vod-root")) throw mm::cli::UsageError("--vod-root DIR is required");
  const std::string root = args.str("vod-root");
  const std::vector<int> all_frames = framesFrom(args);
  const Shard shard = parseShard(args.str("shard", "0/1"));
  const std::string input = args.str("input", "radar");
  if (input != "radar" && input != "lidar")
    throw mm::cli::UsageError("--input must be radar or lidar");
  const int k = args.integer("subsample", 1);
  const int phase = args.integer("subsample-phase", 0);
  if (k < 1) throw mm::cli::UsageError("--subsample must be >= 1");
  if (phase < 0 || phase >= k) throw mm::cli::UsageError("--subsample-phase must be in [0, k)");
  const std::string gt_mode = args.str("gt", "auto");
  if (gt_mode != "auto" && gt_mode != "lidar" && gt_mode != "dense") {
    throw mm::cli::UsageError("--gt must be auto, lidar or dense");
  }
  const std::vector<double> levels =
      parsePercentList("retain-percent", args.str("retain-percent", "100"), false);
  std::vector<double> calibration_levels;
  for (double p : parsePercentList("calibration-levels",
                                   args.str("calibration-levels", "50,68,80,90,95,99"), true)) {
    calibration_levels.push_back(p / 100.0);
  }
  const int stride = args.integer("stride", 1);
  if (stride < 1) throw mm::cli::UsageError("--stride must be >= 1");
  const int repeat = std::max(1, args.integer("repeat", 1));
  mm::DepthEvaluationOptions options;
  options.max_depth = args.number("max-depth", 0.0);
  if (!(options.max_depth >= 0.0)) throw mm::cli::UsageError("--max-depth must be >= 0");
  const bool from_file = args.has("pred");
  // Retention is applied per requested level from one run, so the model runs with 100 %.
  const mm::DepthCompletionParams params = mm::cli::depthModelParams(args);
  if (from_file && all_frames.size() != 1) {
    throw mm::cli::UsageError("--pred evaluates one frame: give a single --frames value");
  }
  const std::string label = args.str("label", from_file ? "file" : mm::toString(params.model));

  std::vector<int> frames;
  for (std::size_t i = 0; i < all_frames.size(); ++i) {
    if (static_cast<int>(i % shard.count) == shard.index) frames.push_back(all_frames[i]);
  }

  mm::DepthCompleter completer(params.threads);
  std::vector<FrameResult> results;
  for (int number : frames) {
    const mm::io::VodFrame frame{root, number};
    FrameResult res;
    res.frame = number;
    mm::StrideGrid grid;
    grid.image = imageSizeOf(args, frame);
    grid.stride = stride;
    const std::size_t n = static_cast<std::size_t>(grid.size());

    // Ground truth.
    const std::string dense_path = denseTruthPath(root, frame);
    const bool dense = gt_mode == "dense" || (gt_mode == "auto" && mm::io::fileExists(dense_path));
    std::vector<float> truth;
    std::vector<Eigen::Vector3f> input_sensor;
    const mm::io::KittiCalib calib = mm::io::readKittiCalib(frame.calib(input));
    const mm::PinholeIntrinsics intrinsics = calib.intrinsics();
    if (!from_file) {
      input_sensor = mm::io::readPoints(frame.points(input), mm::io::parsePointFormat(input));
    }
    if (dense) {
      if (!mm::io::fileExists(dense_path)) throw mm::InputError(dense_path + ": not found");
      int h = 0, w = 0;
      const std::vector<float> depth = readImageNpy(dense_path, &h, &w);
      try {
        truth = mm::sampleDenseGroundTruth(depth, h, w, grid);
      } catch (const mm::InputError& e) {
        throw mm::InputError(dense_path + ": " + e.what());
      }
      res.gt_kind = "dense";
    } else {
      std::vector<Eigen::Vector3f> lidar;
      if (input == "lidar" && !from_file) {
        lidar = subsample(input_sensor, k, phase, false);  // the held-out returns
        if (k == 1) {
          throw mm::cli::UsageError(
              "LiDAR input with LiDAR ground truth needs --subsample k > 1 "
              "(the held-out returns are the ground truth)");
        }
      } else {
        lidar = mm::io::readPoints(frame.points("lidar"), mm::io::parsePointFormat("lidar"));
      }
      const mm::io::KittiCalib lidar_calib = mm::io::readKittiCalib(frame.calib("lidar"));
      truth =
          mm::projectDepthGroundTruth(mm::transformToCamera(lidar, lidar_calib.sensorToCamera()),
                                      lidar_calib.intrinsics(), grid);
      res.gt_points = lidar.size();
      res.gt_kind = "lidar";
    }

    // Prediction on the grid: mean + variance (+inf where none), and which pixels are predicted.
    std::vector<float> depth, variance;
    std::vector<std::uint8_t> predicted;
    if (from_file) {
      int h = 0, w = 0;
      const std::string prefix = args.str("pred");
      depth = readImageNpy(prefix + "_depth.npy", &h, &w);
      if (h != grid.rows() || w != grid.cols()) {
        throw mm::InputError(prefix + "_depth.npy: is " + std::to_string(h) + "x" +
                             std::to_string(w) + " but the grid (--stride " +
                             std::to_string(stride) + ") is " + std::to_string(grid.rows()) + "x" +
                             std::to_string(grid.cols()));
      }
      if (mm::io::fileExists(prefix + "_variance.npy")) {
        variance = readImageNpy(prefix + "_variance.npy", &h, &w);
        if (h != grid.rows() || w != grid.cols()) {
          throw mm::InputError(prefix + "_variance.npy: shape differs from " + prefix +
                               "_depth.npy");
        }
      } else {
        for (double p : levels) {
          if (p < 100.0) {
            throw mm::InputError(prefix +
                                 "_variance.npy: not found; retention below 100% "
                                 "needs the variance");
          }
        }
        variance.assign(n, 0.0f);
      }
      predicted.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        predicted[i] = std::isfinite(depth[i]) && depth[i] > 0.0f && std::isfinite(variance[i]);
      }
    } else {
      input_sensor = subsample(input_sensor, k, phase, true);
      res.input_points = input_sensor.size();
      const auto points_camera = mm::transformToCamera(input_sensor, calib.sensorToCamera());
      std::vector<double> times;
      mm::DepthMap map;
      mm::DepthCompletionParams frame_params = params;
      mm::cli::applyGroundPose(args, frame.pose(), frame_params);  // ground_gp: this frame's pose
      for (int i = 0; i < repeat; ++i) {
        completer.complete(points_camera, intrinsics, grid, frame_params, map);
        times.push_back(map.stats.compute_ms);
      }
      res.runtime_ms = median(times);
      res.input_in_view = map.stats.points_in_view;
      res.ground_source = map.stats.ground_source;
      res.ground_mode = map.stats.ground_mode;
      depth.swap(map.depth);
      variance.swap(map.variance);
      predicted.swap(map.valid);
    }

    std::vector<std::uint8_t> kept(n);
    for (double p : levels) {
      RetentionResult r;
      r.percent = p;
      if (p >= 100.0) {
        kept = predicted;
        r.kept = std::count(kept.begin(), kept.end(), std::uint8_t(1));
      } else {
        r.kept = mm::keepLowestVariance(variance.data(), predicted.data(), n,
                                        mm::retentionCount(p, grid.size()), kept.data());
      }
      r.sums = mm::evaluateDepth(depth.data(), kept.data(), truth.data(), n, options);
      r.calibration = mm::evaluateCalibration(depth.data(), variance.data(), kept.data(),
                                              truth.data(), n, options, calibration_levels);
      res.retention.push_back(r);
    }
    results.push_back(res);
  }

  // JSON: configuration, per frame, aggregate per retention level.
  std::ostringstream config;
  config << "{\"label\": \"" << mm::cli::jsonEscape(label) << "\", \"model\": \""
         << (from_file ? "file" : mm::toString(params.model)) << "\", \"input\": \"" << input
         << "\", \"subsample\": " << k << ", \"subsample_phase\": " << phase << ", \"gt\": \""
         << gt_mode << "\", \"stride\": " << stride
         << ", \"radius_deg\": " << num(params.radius_deg)
         << ", \"max_neighbors\": " << params.max_neighbors
         << ", \"max_depth\": " << num(options.max_depth)
         << ", \"threads\": " << completer.threads() << ", \"vod_root\": \""
         << mm::cli::jsonEscape(root) << "\", \"shard\": [" << shard.index << ", " << shard.count
         << "]}";
  std::vector<double> runtimes;
  for (const FrameResult& f : results)
    runtimes.push_back(f.runtime_ms);
  std::ostringstream aggregate;
  aggregate << "[";
  for (std::size_t l = 0; l < levels.size(); ++l) {
    mm::DepthErrorSums pooled;
    mm::CalibrationCounts calibration;
    calibration.levels = calibration_levels;
    calibration.inside.assign(calibration_levels.size(), 0);
    long long kept = 0;
    for (const FrameResult& f : results) {
      pooled.merge(f.retention[l].sums);
      calibration.merge(f.retention[l].calibration);
      kept += f.retention[l].kept;
    }
    aggregate << (l ? ", " : "") << "{\"retain_percent\": " << num(levels[l])
              << ", \"kept\": " << kept
              << ", \"pooled\": " << metricsJson(mm::DepthMetrics::from(pooled))
              << ", \"mean_over_frames\": " << meanOverFramesJson(results, l)
              << ", \"sums\": " << sumsJson(pooled)
              << ", \"calibration\": " << calibrationJson(calibration) << "}";
  }
  aggregate << "]";

  std::ostringstream full;
  full << "{\n  \"tool\": \"evaluate_depth\",\n  \"config\": " << config.str()
       << ",\n  \"protocol\": \"metrics over ground-truth pixels (finite, > 0, within max_depth) "
          "that have a kept prediction; predictions clipped to [0.001, max_depth]; coverage = "
          "evaluated / ground-truth pixels; RMSE_log uses the natural log; calibration = share of "
          "the evaluated pixels whose truth lies in the central Gaussian interval mean +- z sigma "
          "of each nominal level (sigma^2 = the predicted variance); runtime_ms = model "
          "compute time (median over --repeat)\",\n  \"frames\": [\n";
  for (std::size_t i = 0; i < results.size(); ++i) {
    const FrameResult& f = results[i];
    full << "    {\"frame\": " << f.frame << ", \"gt\": \"" << f.gt_kind
         << "\", \"input_points\": " << f.input_points << ", \"input_in_view\": " << f.input_in_view
         << ", \"gt_points\": " << f.gt_points << ", \"runtime_ms\": " << num(f.runtime_ms)
         << (f.ground_mode.empty() ? ""
                                   : ", \"ground_source\": \"" + f.ground_source +
                                         "\", \"ground_mode\": \"" + f.ground_mode + "\"")
         << ", \"retention\": [";
    for (std::size_t l = 0; l < f.retention.size(); ++l) {
      const RetentionResult& r = f.retention[l];
      full << (l ? ", " : "") << "{\"retain_percent\": " << num(r.percent)
           << ", \"kept\": " << r.kept
           << ", \"metrics\": " << metricsJson(mm::DepthMetrics::from(r.sums))
           << ", \"sums\": " << sumsJson(r.sums)
           << ", \"calibration\": " << calibrationJson(r.calibration) << "}";
    }
    full << "]}" << (i + 1 < results.size() ? "," : "") << "\n";
  }
  full << "  ],\n  \"median_runtime_ms\": " << num(median(runtimes))
       << ",\n  \"aggregate\": " << aggregate.str() << "\n}\n";
  if (args.has("output")) {
    const std::string path = args.str("output");
    std::ofstream out(path);
    out << full.str();
    if (!out) throw mm::InputError(path + ": cannot write");
  }
  std::cout << "{\"config\": " << config.str() << ", \"frames\": " << results.size()
            << ", \"median_runtime_ms\": " << num(median(runtimes))
            << ", \"aggregate\": " << aggregate.str() << "}" << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("evaluate_depth", run, argc, argv);
}
