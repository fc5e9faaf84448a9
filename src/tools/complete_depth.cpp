// complete_depth: dense depth + variance from a sparse radar/LiDAR scan and a KITTI calibration,
// with the reference implementation's models, defaults and output layout.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "common/cli.hpp"
#include "common/depth_options.hpp"
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

void declareOptions(mm::cli::Args& args) {
  mm::cli::declareDepthModelOptions(args);
  args.option("points", 1,
              "scan file: VoD radar .bin (7 floats), LiDAR .bin (4), xyz .bin (3) or .pcd");
  args.option("format", 1, "radar|lidar|xyz|pcd (default: from --sensor, or pcd for *.pcd)");
  args.option("calib", 1, "KITTI calibration with P2 and Tr_velo_to_cam");
  args.option("image-size", 2, "output image size H W");
  args.option("image", 1, "camera image; its size is the output size");
  args.option("vod-root", 1, "View-of-Delft layout root (takes points, calib, image from there)");
  args.option("frame", 1, "VoD frame number, with or without leading zeros");
  args.option("sensor", 1, "radar|lidar", "radar");
  args.option("stride", 1, "output grid step in pixels", "1");
  args.option("retain-percent", 1, "keep this % of all pixels with the lowest variance", "100");
  args.option("output", 1, "write PREFIX_depth.npy, PREFIX_variance.npy, PREFIX_valid.npy");
  args.flag("png", "also write PREFIX_depth.png and PREFIX_variance.png with scale bars");
  args.option("repeat", 1, "repeat the computation N times and report the median", "1");
}

mm::DepthCompletionParams paramsFrom(const mm::cli::Args& args) {
  mm::DepthCompletionParams p = mm::cli::depthModelParams(args);
  p.retain_percent = args.number("retain-percent", p.retain_percent);
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
  mm::cli::Args args("complete_depth",
                     "Dense depth and variance from a sparse radar or LiDAR scan (localized GP in "
                     "the azimuth/elevation domain).");
  declareOptions(args);
  if (!args.parse(argc, argv)) return 0;

  std::string points_path = args.str("points"), calib_path = args.str("calib");
  std::string image_path = args.str("image");
  const std::string sensor = args.str("sensor", "radar");
  if (sensor != "radar" && sensor != "lidar")
    throw mm::cli::UsageError("--sensor must be radar or lidar");
  if (args.has("vod-root")) {
    if (!args.has("frame")) throw mm::cli::UsageError("--vod-root needs --frame");
    const mm::io::VodFrame frame{args.str("vod-root"), mm::io::parseFrameNumber(args.str("frame"))};
    if (points_path.empty()) points_path = frame.points(sensor);
    if (calib_path.empty()) calib_path = frame.calib(sensor);
    if (image_path.empty() && !args.has("image-size") && mm::io::fileExists(frame.image())) {
      image_path = frame.image();
    }
  }
  if (points_path.empty() || calib_path.empty()) {
    throw mm::cli::UsageError("give --points and --calib, or --vod-root and --frame");
  }
  std::string format = args.str("format");
  if (format.empty()) {
    const bool pcd = points_path.size() > 4 && points_path.substr(points_path.size() - 4) == ".pcd";
    format = pcd ? "pcd" : sensor;
  }

  mm::StrideGrid grid;
  grid.stride = args.integer("stride", 1);
  if (grid.stride < 1) throw mm::cli::UsageError("--stride must be >= 1");
  cv::Mat image;  // the camera image: its size, and the guide of image_guided
  if (!image_path.empty()) {
    image = cv::imread(image_path, cv::IMREAD_UNCHANGED);
    if (image.empty()) throw mm::InputError(image_path + ": cannot read or decode image");
  }
  if (args.has("image-size")) {
    const auto& hw = args.list("image-size");
    grid.image = {std::atoi(hw[0].c_str()), std::atoi(hw[1].c_str())};
  } else if (!image.empty()) {
    grid.image = {image.rows, image.cols};
  } else {
    throw mm::cli::UsageError("give --image-size H W or --image FILE");
  }
  if (grid.image.height <= 0 || grid.image.width <= 0) {
    throw mm::cli::UsageError("--image-size must be positive");
  }

  mm::DepthCompletionParams params = paramsFrom(args);
  const std::string frame_pose =
      args.has("vod-root")
          ? mm::io::VodFrame{args.str("vod-root"), mm::io::parseFrameNumber(args.str("frame"))}
                .pose()
          : std::string();
  mm::cli::applyGroundPose(args, frame_pose, params);
  const mm::io::KittiCalib calib = mm::io::readKittiCalib(calib_path);
  const mm::PinholeIntrinsics intrinsics = calib.intrinsics();
  const mm::SensorToCamera extrinsic = calib.sensorToCamera();
  const auto points_sensor = mm::io::readPoints(points_path, mm::io::parsePointFormat(format));
  const auto points_camera = mm::transformToCamera(points_sensor, extrinsic);

  mm::DepthCompleter completer(params.threads);
  const int repeat = std::max(1, args.integer("repeat", 1));
  std::vector<double> times;
  mm::DepthMap result;
  for (int i = 0; i < repeat; ++i) {
    completer.complete(points_camera, intrinsics, grid, params, result, image);
    times.push_back(result.stats.compute_ms);
  }
  const auto& s = result.stats;
  if (s.points_total == s.points_non_finite) {
    std::cerr << "complete_depth: warning: " << points_path
              << " has no usable point; the output is the prior everywhere\n";
  }

  if (args.has("output")) {
    const std::string prefix = args.str("output");
    const std::vector<std::size_t> shape{std::size_t(grid.rows()), std::size_t(grid.cols())};
    mm::io::writeNpy(prefix + "_depth.npy", result.depth.data(), shape);
    mm::io::writeNpy(prefix + "_variance.npy", result.variance.data(), shape);
    mm::io::writeNpy(prefix + "_valid.npy", result.valid.data(), shape);
    if (args.has("png")) {
      writePng(prefix + "_depth.png", result.depth, result.valid, grid, "depth [m]");
      writePng(prefix + "_variance.png", result.variance, result.valid, grid, "variance [m^2]");
    }
  }

  std::ostringstream json;
  json << "{\"model\": \"" << mm::toString(params.model) << "\", \"rows\": " << grid.rows()
       << ", \"cols\": " << grid.cols() << ", \"pixels\": " << s.pixels
       << ", \"predicted\": " << s.predicted << ", \"kept\": " << s.kept
       << ", \"points_total\": " << s.points_total
       << ", \"points_non_finite\": " << s.points_non_finite
       << ", \"points_in_view\": " << s.points_in_view
       << ", \"neighbour_sets\": " << s.neighbour_sets << ", \"shift\": " << s.shift
       << ", \"threads\": " << completer.threads() << ", \"compute_ms\": " << times.front();
  if (repeat > 1) {
    std::sort(times.begin(), times.end());
    json << ", \"repeat\": " << repeat << ", \"median_ms\": " << times[times.size() / 2]
         << ", \"min_ms\": " << times.front();
  }
  json << "}";
  std::cout << json.str() << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("complete_depth", run, argc, argv);
}
