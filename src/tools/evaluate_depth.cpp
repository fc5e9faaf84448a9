// evaluate_depth: depth accuracy of a completion model (or of saved complete_depth output) on
// View-of-Delft-layout frames — MAE, RMSE, RMSE_log, AbsRel and delta<1.25 over the ground-truth
// pixels, per frame and aggregated, at several retention levels from one completion run. Ground
// truth: the LiDAR scan projected into the image (nearest return per pixel), or the exact depth
// image ROOT/depth_gt/NNNNN.npy of the synthetic scene. `--shard i/N` evaluates every N-th frame
// so that a scheduler can spread a dataset over machines; the JSON keeps the raw sums, so shards
// merge exactly (scripts/eval_tables.py merge).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "common/cli.hpp"
#include "common/depth_options.hpp"
#include "common/frame_options.hpp"
#include "common/model_choices_json.hpp"
#include "common/progress.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/common/retain_freed_memory.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/hidden_returns.hpp"
#include "multimodal_nvs/core/depth/retention.hpp"
#include "multimodal_nvs/core/eval/depth_metrics.hpp"
#include "multimodal_nvs/core/io/camera_info_yaml.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace mm = multimodal_nvs;

namespace {

struct Options {
  mm::cli::DepthModelOptions depth;
  mm::cli::FrameOptions frames;
  std::string vod_root, input = "radar", gt = "auto", pred, retain_percent = "100",
                        calibration_levels = "50,68,80,90,95,99", label, output, save_errors;
  int subsample = 1, subsample_phase = 0, stride = 1, repeat = 1;
  double max_depth = 0.0;
  bool quiet = false;
  std::vector<int> image_size;
};

void declareOptions(CLI::App& app, Options& o) {
  const char* in = mm::cli::kRequired;
  app.add_option("--vod-root", o.vod_root,
                 "View-of-Delft layout root (real VoD or make_synthetic_scene output)")
      ->required()
      ->group(in);
  mm::cli::declareFrameOptions(app, o.frames, in,
                               "frames: numbers and ranges, e.g. 549,1047 or 8350-8365", true);
  const char* inputs = mm::cli::kInputs;
  app.add_option("--input", o.input, "radar|lidar: the sensor completed from")
      ->check(CLI::IsMember({"radar", "lidar"}))
      ->group(inputs);
  app.add_option("--subsample", o.subsample,
                 "use every k-th input return (1-in-k); with LiDAR input and LiDAR ground truth "
                 "the other returns become the ground truth")
      ->check(mm::cli::atLeast(1))
      ->group(inputs);
  app.add_option("--subsample-phase", o.subsample_phase,
                 "which return of each k starts the input subsample")
      ->check(mm::cli::atLeast(0))
      ->group(inputs);
  app.add_option("--gt", o.gt,
                 "auto|lidar|dense: ground truth (auto: ROOT/depth_gt/NNNNN.npy when it exists, "
                 "else the LiDAR scan)")
      ->check(CLI::IsMember({"auto", "lidar", "dense"}))
      ->group(inputs);
  app.add_option("--pred", o.pred,
                 "evaluate saved output PREFIX_depth.npy (+ PREFIX_variance.npy for retention) of "
                 "one frame instead of running a model")
      ->group(inputs);
  app.add_option("--image-size", o.image_size, "image size (default: from the frame's image)")
      ->expected(2)
      ->default_str("")
      ->check(mm::cli::atLeast(1))
      ->group(inputs);
  const char* out = mm::cli::kOutput;
  app.add_option("--output", o.output, "write the full JSON (per frame and aggregate) to this file")
      ->group(out);
  app.add_option("--label", o.label, "name of this configuration in the JSON (default: the model)")
      ->group(out);
  app.add_option("--save-errors", o.save_errors,
                 "write DIR/NNNNN_errors.npy per frame: prediction - truth at each ground-truth "
                 "pixel in grid order, NaN where there is no prediction (every prediction, as at "
                 "100 %); runs of several models on the same truth line up entry for entry, for "
                 "comparing them on the pixels they all predict (scripts/eval_tables.py common)")
      ->group(out);
  app.add_option("--stride", o.stride, "grid step in pixels (as complete_depth --stride)")
      ->check(mm::cli::atLeast(1))
      ->group(out);
  app.add_option("--retain-percent", o.retain_percent,
                 "comma list: keep p% of all grid pixels with the lowest variance, evaluated on "
                 "the kept pixels (100: every prediction)")
      ->group(out);
  app.add_option("--calibration-levels", o.calibration_levels,
                 "comma list of nominal coverages (percent, in (0, 100)) of the central Gaussian "
                 "intervals mean +- z sigma whose observed coverage is reported")
      ->group(out);
  app.add_option("--max-depth", o.max_depth,
                 "range cap: ignore ground truth deeper than this (0: none)")
      ->check(mm::cli::atLeast(0))
      ->group(out);
  mm::cli::declareDepthModelOptions(app, o.depth);
  app.add_flag("--quiet", o.quiet, "no progress or throughput on stderr")->group(mm::cli::kOptions);
  app.add_option("--repeat", o.repeat, "run the model N times per frame and report the median time")
      ->check(mm::cli::atLeast(1))
      ->group(mm::cli::kOptions);
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

/// The frame's camera image, decoded once: its size is the output size (without --image-size) and
/// image_guided follows it.
cv::Mat readFrameImage(const mm::io::VodFrame& frame) {
  const std::string path = frame.image();
  if (!mm::io::fileExists(path)) {
    throw mm::InputError(path + ": image not found (give --image-size H W)");
  }
  cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw mm::InputError(path + ": cannot read or decode image");
  return image;
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
  mm::DepthMapStats stats;  // the model's last run (ground_gp, image_guided: its plane and mode)
  std::vector<RetentionResult> retention;
};

mm::json::Json sumsJson(const mm::DepthErrorSums& s) {
  return {{"gt_pixels", s.gt_pixels},
          {"count", s.count},
          {"abs_error", mm::json::number(s.abs_error)},
          {"sq_error", mm::json::number(s.sq_error)},
          {"sq_log_error", mm::json::number(s.sq_log_error)},
          {"abs_rel", mm::json::number(s.abs_rel)},
          {"delta1", s.delta1}};
}

/// [{"level": p, "observed": share, "inside": count, "count": n}, ...] of the central intervals.
mm::json::Json calibrationJson(const mm::CalibrationCounts& c) {
  mm::json::Json out = mm::json::Json::array();
  for (std::size_t i = 0; i < c.levels.size(); ++i) {
    out.push_back({{"level", mm::json::number(c.levels[i])},
                   {"observed", mm::json::number(c.observed(i))},
                   {"inside", c.inside[i]},
                   {"count", c.count}});
  }
  return out;
}

mm::json::Json metricsJson(const mm::DepthMetrics& m) {
  return {{"count", m.count},
          {"gt_pixels", m.gt_pixels},
          {"mae", mm::json::number(m.mae)},
          {"rmse", mm::json::number(m.rmse)},
          {"rmse_log", mm::json::number(m.rmse_log)},
          {"abs_rel", mm::json::number(m.abs_rel)},
          {"delta1", mm::json::number(m.delta1)},
          {"coverage", mm::json::number(m.coverage)}};
}

/// Mean over frames of each metric (frames where it is undefined are skipped).
mm::json::Json meanOverFramesJson(const std::vector<FrameResult>& frames, std::size_t level) {
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
    return mm::json::number(count[i] > 0 ? sum[i] / count[i]
                                         : std::numeric_limits<double>::quiet_NaN());
  };
  return {{"frames", frames.size()}, {"mae", mean(0)},     {"rmse", mean(1)},
          {"rmse_log", mean(2)},     {"abs_rel", mean(3)}, {"delta1", mean(4)},
          {"coverage", mean(5)}};
}

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t mid = v.size() / 2;
  return v.size() % 2 ? v[mid] : 0.5 * (v[mid - 1] + v[mid]);
}

int run(int argc, char** argv) {
  CLI::App app(
      "Depth accuracy (MAE, RMSE, RMSE_log, AbsRel, delta<1.25) of a completion model "
      "against projected LiDAR or exact depth, per frame and aggregated.",
      "evaluate_depth");
  mm::cli::setUp(app,
                 "evaluate_depth --vod-root data/vod --frames 549,1047 --model local_gp_mle "
                 "--retain-percent 100,80 --output eval.json");
  Options o;
  declareOptions(app, o);
  if (!mm::cli::parse(app, argc, argv)) return 0;
  mm::retainFreedMemory();  // every model on every frame allocates tens of MB of per-pixel buffers
  const std::string& root = o.vod_root;
  const std::vector<int> frames = mm::cli::selectedFrames(o.frames);
  const mm::cli::Shard shard = mm::cli::parseShard(o.frames.shard);
  const std::string& input = o.input;
  const int k = o.subsample;
  const int phase = o.subsample_phase;
  if (phase >= k) throw mm::cli::UsageError("--subsample-phase must be in [0, k)");
  const std::string& gt_mode = o.gt;
  const std::vector<double> levels = parsePercentList("retain-percent", o.retain_percent, false);
  std::vector<double> calibration_levels;
  for (double p : parsePercentList("calibration-levels", o.calibration_levels, true)) {
    calibration_levels.push_back(p / 100.0);
  }
  const int stride = o.stride;
  const int repeat = o.repeat;
  mm::DepthEvaluationOptions options;
  options.max_depth = o.max_depth;
  const bool from_file = !o.pred.empty();
  // Retention is applied per requested level from one run, so the model runs with 100 %.
  const mm::DepthCompletionParams params = mm::cli::depthModelParams(o.depth);
  if (from_file && frames.size() != 1) {
    throw mm::cli::UsageError("--pred evaluates one frame: give a single --frames value");
  }
  const std::string label = !o.label.empty() ? o.label
                            : from_file      ? "file"
                                             : mm::toString(params.model);

  if (!o.save_errors.empty()) {
    std::error_code ec;
    if (!std::filesystem::create_directories(o.save_errors, ec) && ec) {
      throw mm::InputError(o.save_errors + ": cannot create the directory (" + ec.message() + ")");
    }
  }

  mm::DepthCompleter completer(params.threads);
  std::vector<FrameResult> results;
  mm::cli::Progress progress("evaluate_depth", static_cast<int>(frames.size()), "frames", o.quiet);
  for (int number : frames) {
    const mm::io::VodFrame frame{root, number};
    FrameResult res;
    res.frame = number;
    // image_guided and ground_gp's sky need the camera image, ground_gp's colours use it where
    // there is one; the others only its size (with --image-size a frame may have no image).
    const bool read_image = o.image_size.empty() || params.needsImage() ||
                            (params.readsImage() && mm::io::fileExists(frame.image()));
    const cv::Mat image = read_image ? readFrameImage(frame) : cv::Mat();
    mm::StrideGrid grid;
    grid.image = o.image_size.empty() ? mm::ImageSize{image.rows, image.cols}
                                      : mm::ImageSize{o.image_size[0], o.image_size[1]};
    grid.stride = stride;
    const std::size_t n = static_cast<std::size_t>(grid.size());

    // Ground truth.
    const std::string dense_path = denseTruthPath(root, frame);
    const bool dense = gt_mode == "dense" || (gt_mode == "auto" && mm::io::fileExists(dense_path));
    std::vector<float> truth;
    std::vector<Eigen::Vector3f> input_sensor;
    if (frame.points(input).empty()) {
      throw mm::cli::UsageError(root + " is in the " + mm::io::toString(frame.layout()) +
                                " layout, which has no " + input + " (use --input lidar)");
    }
    const mm::io::KittiCalib calib = mm::io::readKittiCalib(frame.calib(input));
    const mm::PinholeIntrinsics intrinsics = mm::io::frameIntrinsics(
        calib, mm::io::fileExists(frame.cameraInfo(input)) ? frame.cameraInfo(input) : "",
        grid.image);
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
      const std::string lidar_info =
          mm::io::fileExists(frame.cameraInfo("lidar")) ? frame.cameraInfo("lidar") : "";
      truth = mm::projectDepthGroundTruth(
          mm::transformToCamera(lidar, lidar_calib.sensorToCamera()),
          mm::io::frameIntrinsics(lidar_calib, lidar_info, grid.image), grid);
      res.gt_points = lidar.size();
      res.gt_kind = "lidar";
    }

    // Prediction on the grid: mean + variance (+inf where none), and which pixels are predicted.
    std::vector<float> depth, variance;
    std::vector<std::uint8_t> predicted;
    if (from_file) {
      int h = 0, w = 0;
      const std::string& prefix = o.pred;
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
      mm::cli::applyGroundPose(o.depth, frame.pose(),
                               frame_params);  // ground_gp: this frame's pose
      mm::setScanOrigin(calib.sensorToCamera().col(3), frame_params.ground);
      for (int i = 0; i < repeat; ++i) {
        completer.complete(points_camera, intrinsics, grid, frame_params, map, image);
        times.push_back(map.stats.compute_ms);
      }
      res.runtime_ms = median(times);
      res.input_in_view = map.stats.points_in_view;
      res.stats = map.stats;
      depth.swap(map.depth);
      variance.swap(map.variance);
      predicted.swap(map.valid);
    }

    if (!o.save_errors.empty()) {
      const std::vector<float> errors =
          mm::signedErrorsAtTruth(depth.data(), predicted.data(), truth.data(), n, options);
      mm::io::writeNpy(o.save_errors + "/" + frame.id() + "_errors.npy", errors.data(),
                       {errors.size()});
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
    progress.step(frame.id());
  }

  progress.finish();

  // JSON: configuration, per frame, aggregate per retention level.
  const mm::json::Json config = {{"label", label},
                                 {"model", from_file ? "file" : mm::toString(params.model)},
                                 {"input", input},
                                 {"subsample", k},
                                 {"subsample_phase", phase},
                                 {"gt", gt_mode},
                                 {"stride", stride},
                                 {"radius_deg", mm::json::number(params.radius_deg)},
                                 {"max_neighbors", params.max_neighbors},
                                 {"max_depth", mm::json::number(options.max_depth)},
                                 {"threads", completer.threads()},
                                 {"vod_root", root},
                                 {"shard", {shard.index, shard.count}}};
  std::vector<double> runtimes;
  for (const FrameResult& f : results)
    runtimes.push_back(f.runtime_ms);
  mm::json::Json aggregate = mm::json::Json::array();
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
    aggregate.push_back({{"retain_percent", mm::json::number(levels[l])},
                         {"kept", kept},
                         {"pooled", metricsJson(mm::DepthMetrics::from(pooled))},
                         {"mean_over_frames", meanOverFramesJson(results, l)},
                         {"sums", sumsJson(pooled)},
                         {"calibration", calibrationJson(calibration)}});
  }

  mm::json::Json per_frame = mm::json::Json::array();
  for (const FrameResult& f : results) {
    mm::json::Json retention = mm::json::Json::array();
    for (const RetentionResult& r : f.retention) {
      retention.push_back({{"retain_percent", mm::json::number(r.percent)},
                           {"kept", r.kept},
                           {"metrics", metricsJson(mm::DepthMetrics::from(r.sums))},
                           {"sums", sumsJson(r.sums)},
                           {"calibration", calibrationJson(r.calibration)}});
    }
    per_frame.push_back({{"frame", f.frame},
                         {"gt", f.gt_kind},
                         {"input_points", f.input_points},
                         {"input_in_view", f.input_in_view},
                         {"gt_points", f.gt_points},
                         {"runtime_ms", mm::json::number(f.runtime_ms)}});
    mm::cli::addModelChoices(f.stats, per_frame.back());  // ground_gp, image_guided
    per_frame.back()["retention"] = retention;
  }
  if (!o.output.empty()) {
    const mm::json::Json full = {
        {"tool", "evaluate_depth"},
        {"config", config},
        {"protocol",
         "metrics over ground-truth pixels (finite, > 0, within max_depth) that have a kept "
         "prediction; predictions clipped to [0.001, max_depth]; coverage = evaluated / "
         "ground-truth pixels; RMSE_log uses the natural log; calibration = share of the "
         "evaluated pixels whose truth lies in the central Gaussian interval mean +- z sigma of "
         "each nominal level (sigma^2 = the predicted variance); runtime_ms = model compute time "
         "(median over --repeat)"},
        {"frames", per_frame},
        {"median_runtime_ms", mm::json::number(median(runtimes))},
        {"aggregate", aggregate}};
    mm::json::writeTextFile(o.output, mm::json::document(full));
  }
  const mm::json::Json summary = {{"config", config},
                                  {"frames", results.size()},
                                  {"median_runtime_ms", mm::json::number(median(runtimes))},
                                  {"aggregate", aggregate}};
  std::cout << mm::json::oneLine(summary) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("evaluate_depth", run, argc, argv);
}
