// complete_depth: dense depth + variance from a sparse radar/LiDAR scan and a KITTI calibration,
// with the reference implementation's models, defaults and output layout.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "common/cli.hpp"
#include "common/depth_options.hpp"
#include "common/json_output.hpp"
#include "multimodal_nvs/core/common/colormap.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace mm = multimodal_nvs;

namespace {

struct Options {
  mm::cli::DepthModelOptions depth;
  std::string points, format, calib, image, vod_root, frame, sensor = "radar", output;
  std::vector<int> image_size;
  int stride = 1, repeat = 1;
  double retain_percent = 100.0;
  bool png = false;
};

void declareOptions(CLI::App& app, Options& o) {
  const char* in = mm::cli::kRequired;
  app.add_option("--points", o.points,
                 "scan file: VoD radar .bin (7 floats), LiDAR .bin (4), xyz .bin (3) or .pcd")
      ->group(in);
  app.add_option("--calib", o.calib, "KITTI calibration with P2 and Tr_velo_to_cam")->group(in);
  app.add_option("--image", o.image, "camera image; its size is the output size")->group(in);
  app.add_option("--image-size", o.image_size, "output image size (instead of --image)")
      ->expected(2)
      ->default_str("")
      ->check(mm::cli::atLeast(1))
      ->group(in);
  app.add_option("--vod-root", o.vod_root,
                 "View-of-Delft layout root (instead of the three above: points, calib and image "
                 "of --frame)")
      ->group(in);
  app.add_option("--frame", o.frame, "VoD frame number, with or without leading zeros")->group(in);
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

int run(int argc, char** argv) {
  CLI::App app(
      "Dense depth and variance from a sparse radar or LiDAR scan (localized GP in the "
      "azimuth/elevation domain).",
      "complete_depth");
  mm::cli::setUp(app, "complete_depth --vod-root data/vod --frame 8350 --output out/08350 --png");
  Options o;
  declareOptions(app, o);
  if (!mm::cli::parse(app, argc, argv)) return 0;

  std::string points_path = o.points, calib_path = o.calib, image_path = o.image;
  const std::string& sensor = o.sensor;
  std::string frame_pose;
  if (!o.vod_root.empty()) {
    if (o.frame.empty()) throw mm::cli::UsageError("--vod-root needs --frame");
    const mm::io::VodFrame frame{o.vod_root, mm::io::parseFrameNumber(o.frame)};
    if (points_path.empty()) points_path = frame.points(sensor);
    if (calib_path.empty()) calib_path = frame.calib(sensor);
    if (image_path.empty() && o.image_size.empty() && mm::io::fileExists(frame.image())) {
      image_path = frame.image();
    }
    frame_pose = frame.pose();
  }
  if (points_path.empty() || calib_path.empty()) {
    throw mm::cli::UsageError("give --points and --calib, or --vod-root and --frame");
  }
  std::string format = o.format;
  if (format.empty()) {
    const bool pcd = points_path.size() > 4 && points_path.substr(points_path.size() - 4) == ".pcd";
    format = pcd ? "pcd" : sensor;
  }

  mm::StrideGrid grid;
  grid.stride = o.stride;
  if (!o.image_size.empty()) {
    grid.image = {o.image_size[0], o.image_size[1]};
  } else if (!image_path.empty()) {
    const cv::Mat image = cv::imread(image_path, cv::IMREAD_UNCHANGED);
    if (image.empty()) throw mm::InputError(image_path + ": cannot read or decode image");
    grid.image = {image.rows, image.cols};
  } else {
    throw mm::cli::UsageError("give --image-size H W or --image FILE");
  }

  mm::DepthCompletionParams params = paramsFrom(o);
  mm::cli::applyGroundPose(o.depth, frame_pose, params);
  const mm::io::KittiCalib calib = mm::io::readKittiCalib(calib_path);
  const mm::PinholeIntrinsics intrinsics = calib.intrinsics();
  const mm::SensorToCamera extrinsic = calib.sensorToCamera();
  const auto points_sensor = mm::io::readPoints(points_path, mm::io::parsePointFormat(format));
  const auto points_camera = mm::transformToCamera(points_sensor, extrinsic);

  mm::DepthCompleter completer(params.threads);
  const int repeat = o.repeat;
  std::vector<double> times;
  mm::DepthMap result;
  for (int i = 0; i < repeat; ++i) {
    completer.complete(points_camera, intrinsics, grid, params, result);
    times.push_back(result.stats.compute_ms);
  }
  const auto& s = result.stats;
  if (s.points_total == s.points_non_finite) {
    std::cerr << "complete_depth: warning: " << points_path
              << " has no usable point; the output is the prior everywhere\n";
  }

  if (!o.output.empty()) {
    const std::string& prefix = o.output;
    const std::vector<std::size_t> shape{std::size_t(grid.rows()), std::size_t(grid.cols())};
    mm::io::writeNpy(prefix + "_depth.npy", result.depth.data(), shape);
    mm::io::writeNpy(prefix + "_variance.npy", result.variance.data(), shape);
    mm::io::writeNpy(prefix + "_valid.npy", result.valid.data(), shape);
    if (o.png) {
      writePng(prefix + "_depth.png", result.depth, result.valid, grid, "depth [m]");
      writePng(prefix + "_variance.png", result.variance, result.valid, grid, "variance [m^2]");
    }
  }

  mm::cli::Json json = {{"model", mm::toString(params.model)},
                        {"rows", grid.rows()},
                        {"cols", grid.cols()},
                        {"pixels", s.pixels},
                        {"predicted", s.predicted},
                        {"kept", s.kept},
                        {"points_total", s.points_total},
                        {"points_non_finite", s.points_non_finite},
                        {"points_in_view", s.points_in_view},
                        {"neighbour_sets", s.neighbour_sets},
                        {"shift", mm::cli::number(s.shift, 6)},
                        {"threads", completer.threads()},
                        {"compute_ms", mm::cli::number(times.front(), 6)}};
  if (repeat > 1) {
    std::sort(times.begin(), times.end());
    json["repeat"] = repeat;
    json["median_ms"] = mm::cli::number(times[times.size() / 2], 6);
    json["min_ms"] = mm::cli::number(times.front(), 6);
  }
  std::cout << mm::cli::oneLine(json) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("complete_depth", run, argc, argv);
}
