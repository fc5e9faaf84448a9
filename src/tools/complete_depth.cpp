// complete_depth: dense depth + variance from a sparse radar/LiDAR scan and a KITTI calibration,
// with the reference implementation's models, defaults and output layout.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "common/cli.hpp"
#include "multimodal_nvs/core/depth_completion.hpp"
#include "multimodal_nvs/core/errors.hpp"
#include "multimodal_nvs/core/ground_prior.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/visualization.hpp"

namespace mm = multimodal_nvs;

namespace {

void declareOptions(mm::cli::Args& args) {
  args.option("points", 1, "scan file: VoD radar .bin (7 floats), LiDAR .bin (4), xyz .bin (3) or .pcd");
  args.option("format", 1, "radar|lidar|xyz|pcd (default: from --sensor, or pcd for *.pcd)");
  args.option("calib", 1, "KITTI calibration with P2 and Tr_velo_to_cam");
  args.option("image-size", 2, "output image size H W");
  args.option("image", 1, "camera image; its size is the output size");
  args.option("vod-root", 1, "View-of-Delft layout root (takes points, calib, image from there)");
  args.option("frame", 1, "VoD frame number, with or without leading zeros");
  args.option("sensor", 1, "radar|lidar", "radar");
  args.option("model", 1,
              "local_gp_mle|kernel|nearest|linear|ipbasic|constant (baselines: see baselines.hpp)",
              "local_gp_mle");
  args.option("radius-deg", 1, "neighbourhood radius in degrees", "2");
  args.option("stride", 1, "output grid step in pixels", "1");
  args.option("amplitude", 1, "GP amplitude a (kernel variance a^2)", "25");
  args.option("noise", 1, "GP observation noise sigma", "0.5");
  args.option("length-scale-min", 1, "length-scale search lower bound (deg)", "0.1");
  args.option("length-scale-max", 1, "length-scale search upper bound (deg)", "10");
  args.option("opt-tol", 1, "golden-section tolerance", "0.001");
  args.option("opt-max-iter", 1, "golden-section iterations at most", "64");
  args.option("kernel-length-scale-deg", 1, "kernel-regression length scale", "0.75");
  args.option("shift", 1, "auto|median|mean|none|<metres>", "median");
  args.option("retain-percent", 1, "keep this % of all pixels with the lowest variance", "100");
  args.option("var-threshold", 1, "predictions with larger variance are invalid", "inf");
  args.option("threads", 1, "worker threads (0: all cores)", "0");
  args.option("max-neighbors", 1, "0: exact; K>0: tile approximation with at most K samples", "0");
  args.option("approx-tile", 1, "tile side (grid pixels) of the approximation", "16");
  args.option("ground-pose", 1, "ground_gp: VoD pose file giving the camera's height and tilt "
              "(default with --vod-root: the frame's pose)");
  args.option("pose-key", 1, "key in the pose file", "odomToCamera");
  args.option("camera-height", 1, "ground_gp: camera height above the ground without a pose", "1.3");
  args.option("far-depth", 1, "ground_gp: prior depth above the horizon (0: median depth)", "0");
  args.option("residual-amplitude", 1, "ground_gp: GP amplitude of the residual (0: no GP)", "1");
  args.option("surface-k", 1, "ground_gp: nearest samples per pixel for the surface prior", "8");
  args.option("surface-rank", 1, "ground_gp: which smallest of their depths (1 = minimum)", "2");
  args.option("surface-step-px", 1, "ground_gp: lattice step of the surface prior (pixels)", "16");
  args.option("relative-sigma", 1, "ground_gp: prior std / depth at a sample", "0.25");
  args.option("relative-sigma-per-deg", 1, "ground_gp: growth of prior std / depth per degree", "0.10");
  args.option("output", 1, "write PREFIX_depth.npy, PREFIX_variance.npy, PREFIX_valid.npy");
  args.flag("png", "also write PREFIX_depth.png and PREFIX_variance.png with scale bars");
  args.option("repeat", 1, "repeat the computation N times and report the median", "1");
}

mm::DepthCompletionParams paramsFrom(const mm::cli::Args& args) {
  mm::DepthCompletionParams p;
  p.model = mm::parseDepthModel(args.str("model", "local_gp_mle"));
  p.radius_deg = args.number("radius-deg", p.radius_deg);
  p.gp.amplitude = args.number("amplitude", p.gp.amplitude);
  p.gp.noise = args.number("noise", p.gp.noise);
  p.gp.length_scale_min = args.number("length-scale-min", p.gp.length_scale_min);
  p.gp.length_scale_max = args.number("length-scale-max", p.gp.length_scale_max);
  p.gp.tolerance = args.number("opt-tol", p.gp.tolerance);
  p.gp.max_iterations = args.integer("opt-max-iter", p.gp.max_iterations);
  p.kernel_length_scale_deg = args.number("kernel-length-scale-deg", p.kernel_length_scale_deg);
  p.shift = mm::DepthShift::parse(args.str("shift", "median"));
  p.retain_percent = args.number("retain-percent", p.retain_percent);
  p.var_threshold = args.number("var-threshold", p.var_threshold);
  p.threads = args.integer("threads", 0);
  p.max_neighbors = args.integer("max-neighbors", 0);
  p.approx_tile = args.integer("approx-tile", p.approx_tile);
  p.ground.camera_height = args.number("camera-height", p.ground.camera_height);
  p.ground.far_depth = args.number("far-depth", p.ground.far_depth);
  p.ground.residual_amplitude = args.number("residual-amplitude", p.ground.residual_amplitude);
  p.ground.surface_k = args.integer("surface-k", p.ground.surface_k);
  p.ground.surface_rank = args.integer("surface-rank", p.ground.surface_rank);
  p.ground.surface_step_px = args.integer("surface-step-px", p.ground.surface_step_px);
  p.ground.relative_sigma = args.number("relative-sigma", p.ground.relative_sigma);
  p.ground.relative_sigma_per_deg =
      args.number("relative-sigma-per-deg", p.ground.relative_sigma_per_deg);
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
  if (sensor != "radar" && sensor != "lidar") throw mm::cli::UsageError("--sensor must be radar or lidar");
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
  if (args.has("image-size")) {
    const auto& hw = args.list("image-size");
    grid.image = {std::atoi(hw[0].c_str()), std::atoi(hw[1].c_str())};
  } else if (!image_path.empty()) {
    const cv::Mat image = cv::imread(image_path, cv::IMREAD_UNCHANGED);
    if (image.empty()) throw mm::InputError(image_path + ": cannot read or decode image");
    grid.image = {image.rows, image.cols};
  } else {
    throw mm::cli::UsageError("give --image-size H W or --image FILE");
  }
  if (grid.image.height <= 0 || grid.image.width <= 0) {
    throw mm::cli::UsageError("--image-size must be positive");
  }

  mm::DepthCompletionParams params = paramsFrom(args);
  std::string pose_path = args.str("ground-pose");
  if (pose_path.empty() && args.has("vod-root")) {
    const mm::io::VodFrame frame{args.str("vod-root"), mm::io::parseFrameNumber(args.str("frame"))};
    if (mm::io::fileExists(frame.pose())) pose_path = frame.pose();
  }
  if (params.model == mm::DepthModel::kGroundGp && !pose_path.empty()) {
    const auto plane = mm::GroundPlane::fromCameraToWorld(
        mm::io::readVodPose(pose_path, args.str("pose-key", "odomToCamera")));
    params.ground.up_x = plane.up.x();
    params.ground.up_y = plane.up.y();
    params.ground.up_z = plane.up.z();
    params.ground.camera_height = plane.height;
  }
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
    completer.complete(points_camera, intrinsics, grid, params, result);
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
       << ", \"points_total\": " << s.points_total << ", \"points_non_finite\": "
       << s.points_non_finite << ", \"points_in_view\": " << s.points_in_view
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

int main(int argc, char** argv) { return mm::cli::runTool("complete_depth", run, argc, argv); }
