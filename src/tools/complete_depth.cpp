// complete_depth: dense depth + variance from a sparse radar/LiDAR scan and a KITTI calibration,
// with the reference implementation's models, defaults and output layout.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "common/cli.hpp"
#include "common/depth_options.hpp"
#include "common/frame_options.hpp"
#include "common/model_choices_json.hpp"
#include "common/progress.hpp"
#include "multimodal_nvs/core/common/colormap.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/common/retain_freed_memory.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/hidden_returns.hpp"
#include "multimodal_nvs/core/io/camera_info_yaml.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace mm = multimodal_nvs;

namespace {

struct Options {
  mm::cli::DepthModelOptions depth;
  std::string points, format, calib, camera_info, image, vod_root, frame, sensor = "radar", output;
  std::vector<int> image_size;
  int stride = 1, repeat = 1;
  double retain_percent = 100.0;
  bool png = false, quiet = false;
  mm::cli::FrameOptions frames;
};

void declareOptions(CLI::App& app, Options& o) {
  const char* in = mm::cli::kRequired;
  app.add_option("--points", o.points,
                 "scan file: VoD radar .bin (7 floats), LiDAR .bin (4), xyz .bin (3) or .pcd")
      ->group(in);
  app.add_option("--calib", o.calib, "KITTI calibration with P2 and Tr_velo_to_cam")->group(in);
  app.add_option("--camera-info", o.camera_info,
                 "ROS camera_info YAML: K and lens distortion (plumb_bob, rational_polynomial) "
                 "instead of P2's pinhole (default under --vod-root: calib/NNNNN_camera_info.yaml "
                 "when present)")
      ->group(mm::cli::kInputs);
  app.add_option("--image", o.image, "camera image; its size is the output size")->group(in);
  app.add_option("--image-size", o.image_size, "output image size (instead of --image)")
      ->expected(2)
      ->default_str("")
      ->check(mm::cli::atLeast(1))
      ->group(in);
  app.add_option("--vod-root", o.vod_root,
                 "dataset root, View-of-Delft or KITTI object layout (instead of the three above: "
                 "points, calib and image "
                 "of --frame)")
      ->group(in);
  app.add_option("--frame", o.frame, "frame number, with or without leading zeros")->group(in);
  mm::cli::declareFrameOptions(app, o.frames, in,
                               "many VoD frames in one process, e.g. 8350-8365 or 549,1047 "
                               "(--output is then a directory: OUTPUT/NNNNN_depth.npy, ...)",
                               true);
  app.add_option("--sensor", o.sensor, "radar|lidar")
      ->check(CLI::IsMember({"radar", "lidar"}))
      ->group(mm::cli::kInputs);
  app.add_option("--format", o.format,
                 "radar|lidar|xyz|pcd (default: from --sensor, or pcd for *.pcd)")
      ->group(mm::cli::kInputs);
  app.add_option("--output", o.output,
                 "write PREFIX_depth.npy, PREFIX_variance.npy, PREFIX_valid.npy")
      ->group(mm::cli::kOutput);
  app.add_flag("--png", o.png,
               "also write PREFIX_depth.png and PREFIX_variance.png with scale bars")
      ->group(mm::cli::kOutput);
  app.add_option("--stride", o.stride, "output grid step in pixels")
      ->check(mm::cli::atLeast(1))
      ->group(mm::cli::kOutput);
  app.add_option("--retain-percent", o.retain_percent,
                 "keep this % of all pixels with the lowest variance")
      ->check(CLI::Range(0.0, 100.0))
      ->group(mm::cli::kOutput);
  mm::cli::declareDepthModelOptions(app, o.depth);
  app.add_option("--repeat", o.repeat, "repeat the computation N times and report the median")
      ->check(mm::cli::atLeast(1))
      ->group(mm::cli::kOptions);
  app.add_flag("--quiet", o.quiet, "no progress or throughput on stderr (with --frames)")
      ->group(mm::cli::kOptions);
}

mm::DepthCompletionParams paramsFrom(const Options& o) {
  mm::DepthCompletionParams p = mm::cli::depthModelParams(o.depth);
  p.retain_percent = o.retain_percent;
  p.validate();
  return p;
}

void writePng(const std::string& path, const std::vector<float>& values,
              const std::vector<std::uint8_t>& valid, const mm::StrideGrid& grid,
              const std::string& label) {
  cv::Mat v(grid.rows(), grid.cols(), CV_32FC1, const_cast<float*>(values.data()));
  cv::Mat m(grid.rows(), grid.cols(), CV_8UC1, const_cast<std::uint8_t*>(valid.data()));
  if (!cv::imwrite(path, mm::colorizeWithScaleBar(v, m, 0, 0, label))) {
    throw mm::InputError(path + ": cannot write PNG");
  }
}

/// One frame's inputs and where its outputs go.
struct FrameJob {
  int number = -1;  // -1: files given directly
  std::string points, calib, camera_info, image, pose, format, prefix;
};

bool isPcd(const std::string& path) {
  return path.size() > 4 && path.substr(path.size() - 4) == ".pcd";
}

FrameJob vodJob(const Options& o, int number, const std::string& prefix) {
  const mm::io::VodFrame frame{o.vod_root, number};
  FrameJob job;
  job.number = number;
  job.points = o.points.empty() ? frame.points(o.sensor) : o.points;
  if (frame.points(o.sensor).empty()) {
    throw mm::cli::UsageError(o.vod_root + " is in the " + mm::io::toString(frame.layout()) +
                              " layout, which has no " + o.sensor + " (use --sensor lidar)");
  }
  job.calib = o.calib.empty() ? frame.calib(o.sensor) : o.calib;
  job.camera_info = o.camera_info;
  if (job.camera_info.empty() && mm::io::fileExists(frame.cameraInfo(o.sensor))) {
    job.camera_info = frame.cameraInfo(o.sensor);
  }
  job.image = o.image;
  if (job.image.empty() && o.image_size.empty() && mm::io::fileExists(frame.image())) {
    job.image = frame.image();
  }
  job.pose = frame.pose();
  job.prefix = prefix;
  return job;
}

/// One job for --points/--calib or --vod-root --frame (outputs PREFIX_*), one per frame for
/// --vod-root --frames (outputs OUTPUT/NNNNN_*).
std::vector<FrameJob> jobsFrom(const Options& o) {
  std::vector<FrameJob> jobs;
  const bool many = mm::cli::framesGiven(o.frames);
  if (many) {
    if (o.vod_root.empty()) throw mm::cli::UsageError("--frames needs --vod-root");
    if (!o.frame.empty()) throw mm::cli::UsageError("give --frame or --frames, not both");
    if (!o.points.empty() || !o.calib.empty() || !o.image.empty()) {
      throw mm::cli::UsageError(
          "--frames takes every input from --vod-root; --points, --calib and --image name one "
          "frame's files");
    }
    std::error_code ec;
    if (!o.output.empty() && !std::filesystem::create_directories(o.output, ec) && ec) {
      throw mm::InputError(o.output + ": cannot create the output directory (" + ec.message() +
                           ")");
    }
    for (int number : mm::cli::selectedFrames(o.frames)) {
      const std::string id = mm::io::VodFrame{o.vod_root, number}.id();
      jobs.push_back(vodJob(o, number, o.output.empty() ? "" : o.output + "/" + id));
    }
  } else if (!o.vod_root.empty()) {
    if (o.frame.empty()) throw mm::cli::UsageError("--vod-root needs --frame or --frames");
    jobs.push_back(vodJob(o, mm::io::parseFrameNumber(o.frame), o.output));
  } else {
    FrameJob job;
    job.points = o.points;
    job.calib = o.calib;
    job.camera_info = o.camera_info;
    job.image = o.image;
    job.prefix = o.output;
    jobs.push_back(job);
  }
  for (FrameJob& job : jobs) {
    if (job.points.empty() || job.calib.empty()) {
      throw mm::cli::UsageError("give --points and --calib, or --vod-root and --frame(s)");
    }
    if (job.image.empty() && o.image_size.empty()) {
      if (job.number >= 0) {
        throw mm::InputError(mm::io::VodFrame{o.vod_root, job.number}.image() +
                             ": image not found (give --image-size H W)");
      }
      throw mm::cli::UsageError("give --image-size H W or --image FILE");
    }
    job.format = !o.format.empty() ? o.format : isPcd(job.points) ? "pcd" : o.sensor;
  }
  return jobs;
}

/// The frame's camera image (its size, and the guide of image_guided); empty with --image-size.
cv::Mat frameImage(const Options& o, const FrameJob& job) {
  if (!o.image_size.empty()) return cv::Mat();
  cv::Mat image = cv::imread(job.image, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw mm::InputError(job.image + ": cannot read or decode image");
  return image;
}

mm::StrideGrid gridOf(const Options& o, const cv::Mat& image) {
  mm::StrideGrid grid;
  grid.stride = o.stride;
  grid.image = image.empty() ? mm::ImageSize{o.image_size[0], o.image_size[1]}
                             : mm::ImageSize{image.rows, image.cols};
  return grid;
}

void writeOutputs(const Options& o, const std::string& prefix, const mm::DepthMap& result,
                  const mm::StrideGrid& grid) {
  const std::vector<std::size_t> shape{std::size_t(grid.rows()), std::size_t(grid.cols())};
  mm::io::writeNpy(prefix + "_depth.npy", result.depth.data(), shape);
  mm::io::writeNpy(prefix + "_variance.npy", result.variance.data(), shape);
  mm::io::writeNpy(prefix + "_valid.npy", result.valid.data(), shape);
  if (o.png) {
    writePng(prefix + "_depth.png", result.depth, result.valid, grid, "depth [m]");
    writePng(prefix + "_variance.png", result.variance, result.valid, grid, "variance [m^2]");
  }
}

/// One frame's inputs, read and decoded: what the completer needs.
struct LoadedFrame {
  cv::Mat image;
  mm::StrideGrid grid;
  mm::DepthCompletionParams params;
  mm::PinholeIntrinsics intrinsics;
  std::vector<Eigen::Vector3d> points_camera;
};

LoadedFrame loadFrame(const Options& o, const FrameJob& job) {
  LoadedFrame f;
  f.image = frameImage(o, job);
  f.grid = gridOf(o, f.image);
  f.params = paramsFrom(o);
  mm::cli::applyGroundPose(o.depth, job.pose, f.params);
  const mm::io::KittiCalib calib = mm::io::readKittiCalib(job.calib);
  f.intrinsics = mm::io::frameIntrinsics(calib, job.camera_info, f.grid.image);
  const auto points_sensor = mm::io::readPoints(job.points, mm::io::parsePointFormat(job.format));
  const mm::SensorToCamera sensor_to_camera = calib.sensorToCamera();
  f.points_camera = mm::transformToCamera(points_sensor, sensor_to_camera);
  mm::setScanOrigin(sensor_to_camera.col(3), f.params.ground);
  return f;
}

/// Runs one frame (`repeat` times) with the shared completer and prints its JSON line. Returns the
/// compute time of the first run.
double computeFrame(const Options& o, const FrameJob& job, const LoadedFrame& f, bool name_frame,
                    mm::DepthCompleter& completer, mm::DepthMap& result) {
  std::vector<double> times;
  for (int i = 0; i < o.repeat; ++i) {
    completer.complete(f.points_camera, f.intrinsics, f.grid, f.params, result, f.image);
    times.push_back(result.stats.compute_ms);
  }
  const auto& s = result.stats;
  if (s.points_total == s.points_non_finite) {
    std::cerr << "complete_depth: warning: " << job.points
              << " has no usable point; the output is the prior everywhere\n";
  }

  mm::json::Json json = mm::json::Json::object();
  if (name_frame) json["frame"] = job.number;
  json["model"] = mm::toString(f.params.model);
  json["rows"] = f.grid.rows();
  json["cols"] = f.grid.cols();
  json["pixels"] = s.pixels;
  json["predicted"] = s.predicted;
  json["kept"] = s.kept;
  json["points_total"] = s.points_total;
  json["points_non_finite"] = s.points_non_finite;
  json["points_in_view"] = s.points_in_view;
  json["neighbour_sets"] = s.neighbour_sets;
  mm::cli::addModelChoices(s, json);  // ground_gp, image_guided: what the model chose
  json["shift"] = mm::json::number(s.shift, 6);
  json["threads"] = completer.threads();
  json["compute_ms"] = mm::json::number(times.front(), 6);
  if (o.repeat > 1) {
    std::sort(times.begin(), times.end());
    json["repeat"] = o.repeat;
    json["median_ms"] = mm::json::number(times[times.size() / 2], 6);
    json["min_ms"] = mm::json::number(times.front(), 6);
  }
  std::cout << mm::json::oneLine(json) << std::endl;
  return times.front();
}

/// The frames in three overlapping stages: while frame i is completed, frame i+1 is read and
/// decoded and frame i-1's outputs are written (two output maps in turn). Reading, decoding and
/// writing (~80 ms per VoD-sized frame, 21 MB of arrays) otherwise add to every frame's compute
/// time. An error in any stage ends the run with its message, after the frames before it are
/// written.
double completeFrames(const Options& o, const std::vector<FrameJob>& jobs, bool many,
                      mm::DepthCompleter& completer, mm::cli::Progress& progress) {
  double compute_ms = 0.0;
  mm::DepthMap maps[2];
  std::future<void> writes[2];
  std::future<LoadedFrame> next;
  const auto load = [&](std::size_t i) {
    return std::async(std::launch::async, loadFrame, std::cref(o), std::cref(jobs[i]));
  };
  if (!jobs.empty()) next = load(0);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const FrameJob& job = jobs[i];
    const LoadedFrame frame = next.get();
    if (i + 1 < jobs.size()) next = load(i + 1);
    mm::DepthMap& result = maps[i % 2];
    if (writes[i % 2].valid()) writes[i % 2].get();  // frame i-2's outputs, from this map
    compute_ms += computeFrame(o, job, frame, many, completer, result);
    if (!job.prefix.empty()) {
      writes[i % 2] =
          std::async(std::launch::async, [&o, &result, prefix = job.prefix, grid = frame.grid] {
            writeOutputs(o, prefix, result, grid);
          });
    }
    progress.step(job.number >= 0 ? mm::io::VodFrame{o.vod_root, job.number}.id() : job.points);
  }
  for (std::future<void>& write : writes) {
    if (write.valid()) write.get();
  }
  return compute_ms;
}

int run(int argc, char** argv) {
  CLI::App app(
      "Dense depth and variance from a sparse radar or LiDAR scan (localized GP in the "
      "azimuth/elevation domain). One frame, or a list of VoD frames in one process (one JSON line "
      "and one output set per frame).",
      "complete_depth");
  mm::cli::setUp(app,
                 "complete_depth --vod-root data/vod --frame 8350 --output out/08350 --png\n"
                 "  complete_depth --vod-root data/vod --frames 8350-8365 --output out/depth");
  Options o;
  declareOptions(app, o);
  if (!mm::cli::parse(app, argc, argv)) return 0;
  mm::retainFreedMemory();  // each frame (and --repeat) allocates tens of MB of per-pixel buffers
  paramsFrom(o);            // parameter errors before any input is read
  const std::vector<FrameJob> jobs = jobsFrom(o);
  const bool many = mm::cli::framesGiven(o.frames);

  // One completer and two output maps for every frame: the thread pool, the pixel-angle grid (the
  // same camera and grid in a sequence) and the buffers are made once.
  mm::DepthCompleter completer(paramsFrom(o).threads);
  mm::cli::Progress progress("complete_depth", static_cast<int>(jobs.size()), "frames",
                             o.quiet || !many);
  const double compute_ms = completeFrames(o, jobs, many, completer, progress);
  if (many && !o.quiet && !jobs.empty()) {
    progress.finish();
    std::cerr << "complete_depth: depth completion itself "
              << mm::json::number(compute_ms / jobs.size(), 4).dump()
              << " ms per frame; wall time / compute time "
              << mm::json::number(progress.seconds() * 1000.0 / compute_ms, 3).dump() << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("complete_depth", run, argc, argv);
}
