// render_conditioning: renders the kept depth + image of complete_depth into the views of a camera
// trajectory — the conditioning frames of a video diffusion model (GEN3C) — with a classical
// preview fill, the GEN3C input folder and the NVS metrics against recorded ground truth.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <sstream>

#include "common/cli.hpp"
#include "multimodal_nvs/core/common/elapsed.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/json_text.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/eval/image_metrics.hpp"
#include "multimodal_nvs/core/eval/nvs_metrics.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/gen3c_export.hpp"
#include "multimodal_nvs/core/render/preview.hpp"
#include "multimodal_nvs/core/render/render_burst.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"

namespace mm = multimodal_nvs;

namespace {

void declareOptions(mm::cli::Args& args) {
  args.option("image", 1, "reference camera image (the one the depth map belongs to)");
  args.option("depth", 1, "depth .npy (H x W float32, <= 0 = not kept), e.g. PREFIX_depth.npy");
  args.option("valid", 1, "optional kept-pixel mask .npy (nonzero = kept), e.g. PREFIX_valid.npy");
  args.option("calib", 1, "KITTI calibration whose P2 gives the image intrinsics");
  args.option("intrinsics", 4, "fx fy cx cy of the image (instead of --calib)");
  args.option("vod-root", 1, "View-of-Delft root: poses (and ground truth images) of --frames");
  args.option("frames", 1, "recorded frame range A-B under --vod-root, e.g. 8350-8365");
  args.option("poses", -1, "explicit VoD pose JSON files, first = reference view");
  args.option("pose-key", 1, "pose key in the JSON files", mm::io::defaultVodPoseKey());
  args.option(
      "preset", 1,
      "forward|backward|left|right|up|down (m), orbit_left|orbit_right|zoom_in|zoom_out (deg)");
  args.option("magnitude", 1, "preset extent at the last frame, metres or degrees");
  args.option("num-frames", 1, "frames to render", std::to_string(mm::kGen3cFrames));
  args.option("size", 2, "render size H W",
              std::to_string(mm::kGen3cHeight) + " " + std::to_string(mm::kGen3cWidth));
  args.option("splat", 1, "gen3c|zbuffer", "gen3c");
  args.option("resize-depth", 1,
              "auto|yes|no: resample image+depth to the render size first (auto: yes for gen3c)",
              "auto");
  args.option("max-depth", 1, "clamp depth to this many metres (0: off)", "100");
  args.option("edge-threshold", 1,
              "drop pixels with (max-min)/mean >= this in a 5x5 window (0: off)", "0.05");
  args.option("output", 1, "output directory");
  args.flag("gen3c", "also write OUTPUT/gen3c/ with the arrays the diffusion stage loads");
  args.option("gt", -1,
              "ground-truth images of the recorded poses (default: VoD images of --frames)");
  args.option("fps", 1, "preview video frame rate", "24");
  args.option("threads", 1, "worker threads (0: all cores)", "0");
}

std::string frameName(int index) {
  char name[16];
  std::snprintf(name, sizeof name, "%03d", index);
  return name;
}

cv::Mat readImage(const std::string& path) {
  if (!mm::io::fileExists(path)) throw mm::InputError(path + ": image not found");
  cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty()) throw mm::InputError(path + ": cannot read or decode image");
  return image;
}

cv::Mat readNpyImage(const std::string& path, const std::string& what) {
  const mm::io::NpyArray array = mm::io::readNpy(path);
  if (array.shape.size() != 2 || array.shape[0] == 0 || array.shape[1] == 0) {
    throw mm::InputError(path + ": " + what + " must be a 2-D array (H x W)");
  }
  const std::vector<float> values = array.asFloat();
  cv::Mat out(static_cast<int>(array.shape[0]), static_cast<int>(array.shape[1]), CV_32FC1);
  std::copy(values.begin(), values.end(), out.ptr<float>(0));
  return out;
}

/// The stride grid of the image that `depth` (complete_depth --stride s output) sits on.
mm::StrideGrid depthGrid(const cv::Mat& image, const cv::Mat& depth,
                         const std::string& depth_path) {
  if (const auto grid = mm::strideGridOfSize({image.rows, image.cols}, {depth.rows, depth.cols})) {
    return *grid;
  }
  throw mm::InputError(depth_path + ": depth map is " + std::to_string(depth.rows) + "x" +
                       std::to_string(depth.cols) + " but the image is " +
                       std::to_string(image.rows) + "x" + std::to_string(image.cols) +
                       " (neither the same size nor a complete_depth stride grid of it)");
}

struct RecordedInput {
  std::vector<std::string> pose_files;
  std::vector<std::string> gt_files;
};

RecordedInput recordedInputFrom(const mm::cli::Args& args) {
  RecordedInput in;
  if (args.has("frames")) {
    if (!args.has("vod-root")) throw mm::cli::UsageError("--frames needs --vod-root");
    const std::string range = args.str("frames");
    const std::size_t dash = range.find('-');
    if (dash == std::string::npos) throw mm::cli::UsageError("--frames must look like A-B");
    const int a = mm::io::parseFrameNumber(range.substr(0, dash));
    const int b = mm::io::parseFrameNumber(range.substr(dash + 1));
    if (b < a) throw mm::cli::UsageError("--frames A-B needs A <= B");
    for (int f = a; f <= b; ++f) {
      const mm::io::VodFrame frame{args.str("vod-root"), f};
      in.pose_files.push_back(frame.pose());
      in.gt_files.push_back(frame.image());
    }
    // Ground truth is optional for VoD: use it only when every recorded frame has its image.
    for (const std::string& gt : in.gt_files) {
      if (!mm::io::fileExists(gt)) {
        in.gt_files.clear();
        break;
      }
    }
  } else {
    in.pose_files = args.list("poses");
  }
  if (args.has("gt")) in.gt_files = args.list("gt");
  return in;
}

std::string camerasJson(const mm::Trajectory& traj, const std::string& source) {
  std::ostringstream out;
  out << std::setprecision(12);
  out << "{\n  \"convention\": \"w2c maps the reference camera frame (OpenCV axes) to each target "
         "camera; K is at the render size\",\n  \"source\": \""
      << mm::jsonEscape(source) << "\",\n  \"size\": [" << traj.size.height << ", "
      << traj.size.width << "],\n  \"recorded_frames\": [";
  for (std::size_t i = 0; i < traj.recorded_frames.size(); ++i) {
    out << (i ? ", " : "") << traj.recorded_frames[i];
  }
  out << "],\n  \"frames\": [\n";
  for (std::size_t i = 0; i < traj.cameras.size(); ++i) {
    const mm::TargetCamera& cam = traj.cameras[i];
    out << "    {\"index\": " << i << ", \"w2c\": [";
    for (int r = 0; r < 4; ++r) {
      out << (r ? ", " : "") << "[";
      for (int c = 0; c < 4; ++c)
        out << (c ? ", " : "") << cam.world_to_camera(r, c);
      out << "]";
    }
    const mm::PinholeIntrinsics& k = cam.intrinsics;
    out << "], \"K\": [[" << k.fx << ", 0, " << k.cx << "], [0, " << k.fy << ", " << k.cy
        << "], [0, 0, 1]]}" << (i + 1 < traj.cameras.size() ? "," : "") << "\n";
  }
  out << "  ]\n}\n";
  return out.str();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw mm::InputError(path + ": cannot write");
}

void writePng(const std::string& path, const cv::Mat& image) {
  // Fast compression: 3 x 121 frames of 704x1280 otherwise dominate the run time.
  if (!cv::imwrite(path, image, {cv::IMWRITE_PNG_COMPRESSION, 1})) {
    throw mm::InputError(path + ": cannot write PNG");
  }
}

/// Opens an mp4 (mp4v) writer, or an MJPG .avi when this OpenCV has no mp4 encoder.
cv::VideoWriter openPreviewVideo(const std::string& output, double fps, cv::Size size,
                                 std::string& path, std::string& codec) {
  cv::VideoWriter writer;
  path = output + "/preview.mp4";
  codec = "mp4v";
  if (writer.open(path, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps, size)) return writer;
  std::remove(path.c_str());
  path = output + "/preview.avi";
  codec = "MJPG";
  if (writer.open(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, size)) {
    std::cerr << "render_conditioning: note: no mp4 encoder in this OpenCV build; wrote the "
                 "preview video as MJPG "
              << path << "\n";
    return writer;
  }
  std::cerr << "render_conditioning: warning: no video encoder available; no preview video\n";
  path.clear();
  codec.clear();
  return writer;
}

int run(int argc, char** argv) {
  mm::cli::Args args("render_conditioning",
                     "Renders the kept depth + image into a camera trajectory: conditioning frames "
                     "with hole masks, a classical preview, GEN3C's input arrays and NVS metrics.");
  declareOptions(args);
  if (!args.parse(argc, argv)) return 0;
  for (const char* required : {"image", "depth", "output"}) {
    if (!args.has(required))
      throw mm::cli::UsageError(std::string("--") + required + " is required");
  }
  const int trajectory_sources = int(args.has("frames") || args.has("vod-root")) +
                                 int(args.has("poses")) + int(args.has("preset"));
  if (trajectory_sources != 1) {
    throw mm::cli::UsageError(
        "give exactly one trajectory: --vod-root DIR --frames A-B, "
        "--poses FILES..., or --preset NAME --magnitude X");
  }
  if (args.has("preset") != args.has("magnitude")) {
    throw mm::cli::UsageError("--preset and --magnitude go together");
  }
  if (args.has("calib") == args.has("intrinsics")) {
    throw mm::cli::UsageError("give exactly one of --calib FILE or --intrinsics fx fy cx cy");
  }

  const auto& size_args = args.list("size");
  const mm::ImageSize render_size{
      size_args.empty() ? mm::kGen3cHeight : std::atoi(size_args[0].c_str()),
      size_args.empty() ? mm::kGen3cWidth : std::atoi(size_args[1].c_str())};
  if (render_size.height <= 0 || render_size.width <= 0) {
    throw mm::cli::UsageError("--size H W must be positive");
  }
  const int num_frames = args.integer("num-frames", mm::kGen3cFrames);
  if (num_frames < 1) throw mm::cli::UsageError("--num-frames must be >= 1");
  mm::SplatParams splat;
  splat.mode = mm::parseSplatMode(args.str("splat", "gen3c"));

  // Inputs.
  const std::string image_path = args.str("image"), depth_path = args.str("depth");
  const cv::Mat image = readImage(image_path);
  const cv::Mat depth = readNpyImage(depth_path, "depth");
  cv::Mat valid;
  if (args.has("valid")) {
    cv::Mat v = readNpyImage(args.str("valid"), "valid mask");
    if (v.size() != depth.size()) {
      throw mm::InputError(args.str("valid") + ": valid mask is " + std::to_string(v.rows) + "x" +
                           std::to_string(v.cols) + " but " + depth_path + " is " +
                           std::to_string(depth.rows) + "x" + std::to_string(depth.cols));
    }
    valid = v != 0.0f;
  }
  mm::PinholeIntrinsics k_image;
  if (args.has("calib")) {
    k_image = mm::io::readKittiCalib(args.str("calib")).intrinsics();
  } else {
    const auto& v = args.list("intrinsics");
    k_image = {std::atof(v[0].c_str()), std::atof(v[1].c_str()), std::atof(v[2].c_str()),
               std::atof(v[3].c_str())};
    k_image.validate("--intrinsics");
  }
  const mm::StrideGrid grid = depthGrid(image, depth, depth_path);
  const cv::Mat grid_image = mm::sampleImageOnGrid(image, grid);
  const mm::PinholeIntrinsics k_grid = grid.gridIntrinsics(k_image);

  mm::BackprojectionParams prep;
  const std::optional<mm::DepthResize> resize =
      mm::parseDepthResize(args.str("resize-depth", "auto"));
  if (!resize) throw mm::cli::UsageError("--resize-depth must be auto, yes or no");
  prep.resize_to_render = mm::resizesDepthToRender(*resize, splat.mode);
  prep.render_size = render_size;
  prep.max_depth = static_cast<float>(args.number("max-depth", 100.0));
  prep.edge_threshold = static_cast<float>(args.number("edge-threshold", 0.05));
  const auto t_cloud = std::chrono::steady_clock::now();
  const mm::ColoredCloud cloud = mm::buildColoredCloud(depth, valid, grid_image, k_grid, prep);
  const double cloud_ms = mm::millisecondsSince(t_cloud);

  // Trajectory.
  const mm::PinholeIntrinsics k_target =
      k_image.scaledTo(image.rows, image.cols, render_size.height, render_size.width);
  mm::Trajectory trajectory;
  std::string source;
  RecordedInput recorded;
  if (args.has("preset")) {
    const mm::TrajectoryPreset preset = mm::parseTrajectoryPreset(args.str("preset"));
    const double magnitude = args.number("magnitude", 0.0);
    trajectory = mm::presetTrajectory(preset, magnitude, num_frames, k_target, render_size,
                                      cloud.medianDepth());
    source = "preset " + mm::toString(preset) + " " + mm::jsonNumber(magnitude) + " " +
             mm::magnitudeUnit(preset);
    if (args.has("gt")) throw mm::cli::UsageError("--gt needs a recorded trajectory, not a preset");
  } else {
    recorded = recordedInputFrom(args);
    const std::string key = args.str("pose-key", mm::io::defaultVodPoseKey());
    std::vector<Eigen::Matrix4d> poses;
    for (const std::string& file : recorded.pose_files)
      poses.push_back(mm::io::readVodPose(file, key));
    trajectory = mm::recordedTrajectory(poses, num_frames, k_target, render_size);
    source = "recorded " + key + " (" + std::to_string(poses.size()) + " poses, first " +
             recorded.pose_files.front() + ")";
    if (!recorded.gt_files.empty() && recorded.gt_files.size() != poses.size()) {
      throw mm::InputError("--gt has " + std::to_string(recorded.gt_files.size()) +
                           " images but the trajectory has " + std::to_string(poses.size()) +
                           " recorded poses");
    }
  }

  // Outputs.
  const std::string output = args.str("output");
  for (const char* sub : {"frames", "masks", "preview"})
    mm::makeDirectories(output + "/" + sub);
  writeText(output + "/cameras.json", camerasJson(trajectory, source));
  std::string video_path, video_codec;
  cv::VideoWriter video =
      openPreviewVideo(output, args.number("fps", 24.0),
                       cv::Size(render_size.width, render_size.height), video_path, video_codec);
  std::optional<mm::Gen3cBurstExport> gen3c;
  if (args.has("gen3c")) {
    if (const auto warning = mm::gen3cSizeWarning(num_frames, render_size)) {
      std::cerr << "render_conditioning: warning: " << *warning << "\n";
    }
    gen3c.emplace(output + "/gen3c", image, num_frames, render_size,
                  mm::Gen3cFolderWrite::kInPlace);
  }

  // Ground truth per output frame index (empty where there is none).
  std::vector<std::string> gt_of_frame(static_cast<std::size_t>(num_frames));
  for (std::size_t j = 0; j < recorded.gt_files.size(); ++j) {
    gt_of_frame[static_cast<std::size_t>(trajectory.recorded_frames[j])] = recorded.gt_files[j];
  }

  mm::PointSplatter splatter(args.integer("threads", 0));
  mm::ThreadPool io_pool(splatter.threads());
  std::vector<mm::NvsFrameMetrics> metrics;
  double min_coverage = 1.0;
  const auto t_all = std::chrono::steady_clock::now();
  // A chunk at a time: its PNGs and metrics in parallel, then video and export in frame order.
  const mm::BurstStats stats = mm::renderBurstChunks(
      splatter, cloud, trajectory, splat,
      [&](int first, const std::vector<mm::RenderedFrame>& frames) {
        const int count = static_cast<int>(frames.size());
        std::vector<cv::Mat> previews(static_cast<std::size_t>(count));
        std::vector<mm::NvsFrameMetrics> chunk_metrics(static_cast<std::size_t>(count));
        io_pool.parallelFor(count, [&](long long i, int) {
          const int index = first + static_cast<int>(i);
          const mm::RenderedFrame& f = frames[static_cast<std::size_t>(i)];
          cv::Mat preview = mm::fillHolesPushPull(f.bgr, f.mask);
          const std::string& gt_path = gt_of_frame[static_cast<std::size_t>(index)];
          if (!gt_path.empty()) {
            chunk_metrics[static_cast<std::size_t>(i)] =
                mm::nvsFrameMetrics(index, gt_path, f, preview,
                                    mm::groundTruthAtRenderSize(readImage(gt_path), render_size));
          }
          mm::drawPreviewLabel(preview);
          writePng(output + "/frames/" + frameName(index) + ".png", f.bgr);
          writePng(output + "/masks/" + frameName(index) + ".png", f.mask);
          writePng(output + "/preview/" + frameName(index) + ".png", preview);
          previews[static_cast<std::size_t>(i)] = preview;
        });
        for (int i = 0; i < count; ++i) {
          const mm::RenderedFrame& f = frames[static_cast<std::size_t>(i)];
          min_coverage = std::min(min_coverage, mm::coverage(f.mask));
          if (video.isOpened()) video.write(previews[static_cast<std::size_t>(i)]);
          if (gen3c) gen3c->append(f);
          if (!gt_of_frame[static_cast<std::size_t>(first + i)].empty()) {
            metrics.push_back(chunk_metrics[static_cast<std::size_t>(i)]);
          }
        }
      });
  video.release();
  if (gen3c) gen3c->finish();
  if (!metrics.empty())
    writeText(output + "/metrics.json", mm::nvsMetricsJson(metrics, mm::toString(splat.mode)));
  const double total_ms = mm::millisecondsSince(t_all);

  const double mean_psnr = mm::finiteMean(metrics, &mm::NvsFrameMetrics::psnr, false);
  const double mean_ssim = mm::finiteMean(metrics, &mm::NvsFrameMetrics::ssim, false);
  const double mean_cov_psnr = mm::finiteMean(metrics, &mm::NvsFrameMetrics::covered_psnr, false);
  const double mean_cov = mm::finiteMean(metrics, &mm::NvsFrameMetrics::coverage, false);
  std::ostringstream json;
  json << "{\"frames\": " << num_frames << ", \"size\": [" << render_size.height << ", "
       << render_size.width << "], \"splat\": \"" << mm::toString(splat.mode)
       << "\", \"trajectory\": \"" << mm::jsonEscape(source) << "\", \"points\": " << cloud.size()
       << ", \"depth_stride\": " << grid.stride
       << ", \"resized_to_render\": " << (prep.resize_to_render ? "true" : "false")
       << ", \"threads\": " << splatter.threads() << ", \"cloud_ms\": " << mm::jsonNumber(cloud_ms)
       << ", \"render_ms\": " << mm::jsonNumber(stats.render_ms)
       << ", \"total_ms\": " << mm::jsonNumber(total_ms)
       << ", \"min_coverage\": " << mm::jsonNumber(min_coverage) << ", \"video\": "
       << (video_path.empty() ? "null" : "\"" + mm::jsonEscape(video_path) + "\"")
       << ", \"video_codec\": " << (video_codec.empty() ? "null" : "\"" + video_codec + "\"")
       << ", \"gen3c\": " << (gen3c ? "\"" + mm::jsonEscape(output + "/gen3c") + "\"" : "null");
  if (!metrics.empty()) {
    json << ", \"metrics\": {\"gt_frames\": " << metrics.size()
         << ", \"psnr\": " << mm::jsonNumber(mean_psnr)
         << ", \"ssim\": " << mm::jsonNumber(mean_ssim)
         << ", \"covered_psnr\": " << mm::jsonNumber(mean_cov_psnr)
         << ", \"coverage\": " << mm::jsonNumber(mean_cov) << "}";
  }
  json << ", \"output\": \"" << mm::jsonEscape(output) << "\"}";
  std::cout << json.str() << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("render_conditioning", run, argc, argv);
}
