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
#include "common/frame_options.hpp"
#include "common/progress.hpp"
#include "multimodal_nvs/core/common/elapsed.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/common/retain_freed_memory.hpp"
#include "multimodal_nvs/core/eval/image_metrics.hpp"
#include "multimodal_nvs/core/eval/nvs_metrics.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/png_writer.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/burst_pipeline.hpp"
#include "multimodal_nvs/core/render/gen3c_export.hpp"
#include "multimodal_nvs/core/render/preview.hpp"
#include "multimodal_nvs/core/render/render_burst.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"

namespace mm = multimodal_nvs;

namespace {

struct Options {
  std::string image, depth, valid, calib, output, vod_root, preset, splat = "gen3c",
                                                                    resize_depth = "auto";
  std::string pose_key = mm::io::defaultVodPoseKey();
  mm::cli::FrameOptions frames;
  std::vector<double> intrinsics;
  std::vector<std::string> poses, gt;
  double magnitude = 0.0, max_depth = 100.0, edge_threshold = 0.05, fps = 24.0;
  int num_frames = mm::kGen3cFrames, threads = 0, png_level = mm::io::kPngStored;
  std::vector<int> size{mm::kGen3cHeight, mm::kGen3cWidth};
  bool gen3c = false, quiet = false;
};

void declareOptions(CLI::App& app, Options& o) {
  const char* in = mm::cli::kRequired;
  app.add_option("--image", o.image, "reference camera image (the one the depth map belongs to)")
      ->required()
      ->group(in);
  app.add_option("--depth", o.depth,
                 "depth .npy (H x W float32, <= 0 = not kept), e.g. PREFIX_depth.npy")
      ->required()
      ->group(in);
  app.add_option("--output", o.output, "output directory")->required()->group(in);
  app.add_option("--calib", o.calib, "KITTI calibration whose P2 gives the image intrinsics")
      ->group(in);
  app.add_option("--intrinsics", o.intrinsics, "fx fy cx cy of the image (instead of --calib)")
      ->expected(4)
      ->default_str("")
      ->check(mm::cli::finite())
      ->group(in);
  const char* trajectory = "Trajectory (exactly one: recorded frames, pose files or a preset)";
  app.add_option("--vod-root", o.vod_root,
                 "View-of-Delft root: poses (and ground-truth images) of --frames")
      ->group(trajectory);
  mm::cli::declareFrameOptions(app, o.frames, trajectory,
                               "recorded frames under --vod-root, e.g. 8350-8365 (first = the "
                               "reference view)",
                               false);
  app.add_option("--poses", o.poses, "explicit VoD pose JSON files, first = reference view")
      ->group(trajectory);
  mm::cli::declarePoseKeyOption(app, o.pose_key, trajectory,
                                "whose relative motion is the recorded trajectory");
  app.add_option("--preset", o.preset,
                 "forward|backward|left|right|up|down (m), orbit_left|orbit_right|zoom_in|zoom_out "
                 "(deg); needs no pose")
      ->group(trajectory);
  app.add_option("--magnitude", o.magnitude, "preset extent at the last frame, metres or degrees")
      ->check(mm::cli::finite())
      ->group(trajectory);
  app.add_option("--gt", o.gt,
                 "ground-truth images of the recorded poses (default: VoD images of --frames)")
      ->group(trajectory);
  const char* out = mm::cli::kOutput;
  app.add_option("--valid", o.valid,
                 "optional kept-pixel mask .npy (nonzero = kept), e.g. PREFIX_valid.npy")
      ->group(mm::cli::kInputs);
  app.add_option("--num-frames", o.num_frames, "frames to render")
      ->check(mm::cli::atLeast(1))
      ->group(out);
  app.add_option("--size", o.size, "render size H W")
      ->expected(2)
      ->check(mm::cli::atLeast(1))
      ->group(out);
  app.add_option("--splat", o.splat, "gen3c|zbuffer")->group(out);
  app.add_option("--resize-depth", o.resize_depth,
                 "auto|yes|no: resample image+depth to the render size first (auto: yes for gen3c)")
      ->group(out);
  app.add_option("--max-depth", o.max_depth, "clamp depth to this many metres (0: off)")
      ->check(mm::cli::atLeast(0))
      ->group(out);
  app.add_option("--edge-threshold", o.edge_threshold,
                 "drop pixels with (max-min)/mean >= this in a 5x5 window (0: off)")
      ->check(mm::cli::atLeast(0))
      ->group(out);
  app.add_flag("--gen3c", o.gen3c,
               "also write OUTPUT/gen3c/ with the arrays the diffusion stage loads")
      ->group(out);
  app.add_option("--png-level", o.png_level,
                 "compression of frames/*.png, 0-12 (0: stored, 2.7 MB per 704x1280 frame, "
                 "~2 ms; 1: ~1.3 MB, ~15 ms; masks are compressed at least at 1)")
      ->check(CLI::Range(mm::io::kPngStored, mm::io::kPngMaxLevel))
      ->group(out);
  app.add_option("--fps", o.fps, "preview video frame rate")
      ->check(mm::cli::positive())
      ->group(out);
  app.add_option("--threads", o.threads, "worker threads (0: all cores)")
      ->check(mm::cli::atLeast(0))
      ->group(mm::cli::kOptions);
  app.add_flag("--quiet", o.quiet, "no progress or throughput on stderr")->group(mm::cli::kOptions);
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

RecordedInput recordedInputFrom(const Options& o) {
  RecordedInput in;
  if (mm::cli::framesGiven(o.frames)) {
    if (o.vod_root.empty()) throw mm::cli::UsageError("--frames needs --vod-root");
    for (int f : mm::cli::selectedFrames(o.frames)) {
      const mm::io::VodFrame frame{o.vod_root, f};
      if (frame.pose().empty()) {
        throw mm::cli::UsageError(o.vod_root + " is in the " + mm::io::toString(frame.layout()) +
                                  " layout, which has no poses: give --preset or --poses");
      }
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
    in.pose_files = o.poses;
  }
  if (!o.gt.empty()) in.gt_files = o.gt;
  return in;
}

std::string camerasJson(const mm::Trajectory& traj, const std::string& source) {
  auto number = [](double v) { return mm::json::number(v, 12); };
  mm::json::Json frames = mm::json::Json::array();
  for (std::size_t i = 0; i < traj.cameras.size(); ++i) {
    const mm::TargetCamera& cam = traj.cameras[i];
    mm::json::Json w2c = mm::json::Json::array();
    for (int r = 0; r < 4; ++r) {
      mm::json::Json row = mm::json::Json::array();
      for (int c = 0; c < 4; ++c)
        row.push_back(number(cam.world_to_camera(r, c)));
      w2c.push_back(row);
    }
    const mm::PinholeIntrinsics& k = cam.intrinsics;
    frames.push_back(
        {{"index", i},
         {"w2c", w2c},
         {"K", {{number(k.fx), 0, number(k.cx)}, {0, number(k.fy), number(k.cy)}, {0, 0, 1}}}});
  }
  const mm::json::Json out = {
      {"convention",
       "w2c maps the reference camera frame (OpenCV axes) to each target camera; K is at the "
       "render size"},
      {"source", source},
      {"size", {traj.size.height, traj.size.width}},
      {"recorded_frames", traj.recorded_frames},
      {"frames", frames}};
  return mm::json::document(out);
}

void writeJpeg(const std::string& path, const cv::Mat& image) {
  // The hole-filled previews are for looking at (the video shows the same frames): JPEG at
  // quality 95 encodes a 704x1280 frame in ~4 ms where PNG took ~25-60 ms (they are noisy after
  // the fill: 1.2 MB each), the largest single cost of a 121-frame export.
  if (!cv::imwrite(path, image, {cv::IMWRITE_JPEG_QUALITY, 95})) {
    throw mm::InputError(path + ": cannot write JPEG");
  }
}

/// The preview video's frame size: the render size scaled to at most kPreviewVideoWidth pixels
/// wide (what the demo report shows; the full-size previews are the JPEGs), even sides for H.264's
/// 4:2:0 chroma. H.264 at the full 704x1280 added 5-6 s of CPU to a 121-frame export.
constexpr int kPreviewVideoWidth = 640;
cv::Size previewVideoSize(cv::Size render) {
  const double scale = std::min(1.0, double(kPreviewVideoWidth) / render.width);
  const auto even = [](double v) { return std::max(2, 2 * int(std::lround(v / 2))); };
  return {even(render.width * scale), even(render.height * scale)};
}

/// Opens the preview video writer: H.264 ('avc1', what browsers play) in an .mp4 where OpenCV's
/// FFmpeg backend has an H.264 encoder, else MPEG-4 part 2 ('mp4v'), else MJPG in an .avi, with a
/// note naming the fallback. `path` and `codec` are left empty when no encoder opens.
cv::VideoWriter openPreviewVideo(const std::string& output, double fps, cv::Size size,
                                 std::string& path, std::string& codec) {
  struct Candidate {
    const char* codec;
    const char* file;
  };
  static constexpr Candidate kCandidates[] = {
      {"avc1", "/preview.mp4"}, {"mp4v", "/preview.mp4"}, {"MJPG", "/preview.avi"}};
  cv::VideoWriter writer;
  for (const Candidate& candidate : kCandidates) {
    path = output + candidate.file;
    codec = candidate.codec;
    const int fourcc = cv::VideoWriter::fourcc(codec[0], codec[1], codec[2], codec[3]);
    if (writer.open(path, fourcc, fps, size)) {
      if (codec != kCandidates[0].codec) {
        std::cerr << "render_conditioning: note: no H.264 encoder in this OpenCV build; wrote the "
                     "preview video as "
                  << codec << " (browsers may not play it): " << path << "\n";
      }
      return writer;
    }
    std::remove(path.c_str());
  }
  std::cerr << "render_conditioning: warning: no video encoder available; no preview video\n";
  path.clear();
  codec.clear();
  return writer;
}

int run(int argc, char** argv) {
  CLI::App app(
      "Renders the kept depth + image into a camera trajectory: conditioning frames with "
      "hole masks, a classical preview, GEN3C's input arrays and NVS metrics.",
      "render_conditioning");
  mm::cli::setUp(app,
                 "render_conditioning --image data/vod/lidar/training/image_2/08350.jpg --depth "
                 "out/08350_depth.npy --valid out/08350_valid.npy --calib "
                 "data/vod/radar/training/calib/08350.txt --vod-root data/vod --frames 8350-8365 "
                 "--output out/render");
  Options o;
  declareOptions(app, o);
  if (!mm::cli::parse(app, argc, argv)) return 0;
  mm::retainFreedMemory();  // every frame allocates ~30 MB of buffers: no page faults for them
  const int trajectory_sources = int(mm::cli::framesGiven(o.frames) || !o.vod_root.empty()) +
                                 int(!o.poses.empty()) + int(!o.preset.empty());
  if (trajectory_sources != 1) {
    throw mm::cli::UsageError(
        "give exactly one trajectory: --vod-root DIR --frames A-B, "
        "--poses FILES..., or --preset NAME --magnitude X");
  }
  if (o.preset.empty() == mm::cli::given(app, "--magnitude")) {
    throw mm::cli::UsageError("--preset and --magnitude go together");
  }
  if (mm::cli::framesGiven(o.frames)) mm::cli::selectedFrames(o.frames);  // usage errors first
  if (o.calib.empty() == o.intrinsics.empty()) {
    throw mm::cli::UsageError("give exactly one of --calib FILE or --intrinsics fx fy cx cy");
  }

  const mm::ImageSize render_size{o.size[0], o.size[1]};
  const int num_frames = o.num_frames;
  mm::SplatParams splat;
  splat.mode = mm::parseSplatMode(o.splat);

  // Inputs.
  const std::string &image_path = o.image, &depth_path = o.depth;
  const cv::Mat image = readImage(image_path);
  const cv::Mat depth = readNpyImage(depth_path, "depth");
  cv::Mat valid;
  if (!o.valid.empty()) {
    cv::Mat v = readNpyImage(o.valid, "valid mask");
    if (v.size() != depth.size()) {
      throw mm::InputError(o.valid + ": valid mask is " + std::to_string(v.rows) + "x" +
                           std::to_string(v.cols) + " but " + depth_path + " is " +
                           std::to_string(depth.rows) + "x" + std::to_string(depth.cols));
    }
    valid = v != 0.0f;
  }
  mm::PinholeIntrinsics k_image;
  if (!o.calib.empty()) {
    k_image = mm::io::readKittiCalib(o.calib).intrinsics();
  } else {
    const std::vector<double>& v = o.intrinsics;
    k_image = {v[0], v[1], v[2], v[3]};
    k_image.validate("--intrinsics");
  }
  const mm::StrideGrid grid = depthGrid(image, depth, depth_path);
  const cv::Mat grid_image = mm::sampleImageOnGrid(image, grid);
  const mm::PinholeIntrinsics k_grid = grid.gridIntrinsics(k_image);

  mm::BackprojectionParams prep;
  const std::optional<mm::DepthResize> resize = mm::parseDepthResize(o.resize_depth);
  if (!resize) throw mm::cli::UsageError("--resize-depth must be auto, yes or no");
  prep.resize_to_render = mm::resizesDepthToRender(*resize, splat.mode);
  prep.render_size = render_size;
  prep.max_depth = static_cast<float>(o.max_depth);
  prep.edge_threshold = static_cast<float>(o.edge_threshold);
  const auto t_cloud = std::chrono::steady_clock::now();
  const mm::ColoredCloud cloud = mm::buildColoredCloud(depth, valid, grid_image, k_grid, prep);
  const double cloud_ms = mm::millisecondsSince(t_cloud);

  // Trajectory.
  const mm::PinholeIntrinsics k_target =
      k_image.scaledTo(image.rows, image.cols, render_size.height, render_size.width);
  mm::Trajectory trajectory;
  std::string source;
  RecordedInput recorded;
  if (!o.preset.empty()) {
    const mm::TrajectoryPreset preset = mm::parseTrajectoryPreset(o.preset);
    const double magnitude = o.magnitude;
    trajectory = mm::presetTrajectory(preset, magnitude, num_frames, k_target, render_size,
                                      cloud.medianDepth());
    source = "preset " + mm::toString(preset) + " " + mm::json::number(magnitude).dump() + " " +
             mm::magnitudeUnit(preset);
    if (!o.gt.empty()) throw mm::cli::UsageError("--gt needs a recorded trajectory, not a preset");
  } else {
    recorded = recordedInputFrom(o);
    const std::string& key = o.pose_key;
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
  const std::string& output = o.output;
  for (const char* sub : {"frames", "masks", "preview"})
    mm::makeDirectories(output + "/" + sub);
  mm::json::writeTextFile(output + "/cameras.json", camerasJson(trajectory, source));
  std::string video_path, video_codec;
  const cv::Size video_size = previewVideoSize(cv::Size(render_size.width, render_size.height));
  cv::VideoWriter video = openPreviewVideo(output, o.fps, video_size, video_path, video_codec);
  std::optional<mm::Gen3cBurstExport> gen3c;
  if (o.gen3c) {
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

  mm::PointSplatter splatter(o.threads);
  std::vector<mm::NvsFrameMetrics> metrics, metrics_of_frame(static_cast<std::size_t>(num_frames));
  std::vector<cv::Mat> preview_of_frame(static_cast<std::size_t>(num_frames));
  double min_coverage = 1.0;
  const auto t_all = std::chrono::steady_clock::now();
  mm::cli::Progress progress("render_conditioning", num_frames, "frames", o.quiet);
  // Each frame's PNGs, preview, metrics and GEN3C array slices on the workers while the next chunk
  // renders (every frame has its own place in the arrays); only the video in frame order.
  mm::BurstFrameStages stages;
  stages.parallel = [&](int index, mm::RenderedFrame& f, int) {
    const auto i = static_cast<std::size_t>(index);
    cv::Mat preview = mm::fillHolesPushPull(f.bgr, f.mask);
    if (!gt_of_frame[i].empty()) {
      metrics_of_frame[i] =
          mm::nvsFrameMetrics(index, gt_of_frame[i], f, preview,
                              mm::groundTruthAtRenderSize(readImage(gt_of_frame[i]), render_size));
    }
    mm::drawPreviewLabel(preview);
    // The frames stored uncompressed by default: compressing a 704x1280 frame cost ~24 ms through
    // OpenCV (~15 ms at libdeflate's fastest level), the largest CPU cost of a 121-frame export;
    // the masks (two values) compress 40:1 at level 1 in ~2 ms.
    mm::io::writePng(output + "/frames/" + frameName(index) + ".png", f.bgr, o.png_level);
    mm::io::writePng(output + "/masks/" + frameName(index) + ".png", f.mask,
                     std::max(o.png_level, 1));
    writeJpeg(output + "/preview/" + frameName(index) + ".jpg", preview);
    if (gen3c) gen3c->write(index, f);
    if (preview.size() == video_size) {
      preview_of_frame[i] = preview;
    } else {
      cv::resize(preview, preview_of_frame[i], video_size, 0, 0, cv::INTER_AREA);
    }
  };
  stages.ordered = [&](int index, mm::RenderedFrame& f) {
    const auto i = static_cast<std::size_t>(index);
    progress.step();
    min_coverage = std::min(min_coverage, mm::coverage(f.mask));
    if (video.isOpened()) video.write(preview_of_frame[i]);
    preview_of_frame[i].release();
    if (!gt_of_frame[i].empty()) metrics.push_back(metrics_of_frame[i]);
  };
  mm::BurstPipelineOptions pipeline;
  pipeline.workers = splatter.threads();
  const mm::BurstStats stats =
      mm::renderBurstPipelined(splatter, cloud, trajectory, splat, stages, pipeline);
  video.release();
  if (gen3c) gen3c->finish();
  progress.finish();
  if (!metrics.empty())
    mm::json::writeTextFile(output + "/metrics.json",
                            mm::nvsMetricsJson(metrics, mm::toString(splat.mode)));
  const double total_ms = mm::millisecondsSince(t_all);

  const double mean_psnr = mm::finiteMean(metrics, &mm::NvsFrameMetrics::psnr, false);
  const double mean_ssim = mm::finiteMean(metrics, &mm::NvsFrameMetrics::ssim, false);
  const double mean_cov_psnr = mm::finiteMean(metrics, &mm::NvsFrameMetrics::covered_psnr, false);
  const double mean_cov = mm::finiteMean(metrics, &mm::NvsFrameMetrics::coverage, false);
  mm::json::Json json = {
      {"frames", num_frames},
      {"size", {render_size.height, render_size.width}},
      {"splat", mm::toString(splat.mode)},
      {"trajectory", source},
      {"points", cloud.size()},
      {"depth_stride", grid.stride},
      {"resized_to_render", prep.resize_to_render},
      {"threads", splatter.threads()},
      {"cloud_ms", mm::json::number(cloud_ms)},
      {"render_ms", mm::json::number(stats.render_ms)},
      {"total_ms", mm::json::number(total_ms)},
      {"min_coverage", mm::json::number(min_coverage)},
      {"video", video_path.empty() ? mm::json::Json() : mm::json::Json(video_path)},
      {"video_codec", video_codec.empty() ? mm::json::Json() : mm::json::Json(video_codec)},
      {"gen3c", gen3c ? mm::json::Json(output + "/gen3c") : mm::json::Json()}};
  if (!metrics.empty()) {
    json["metrics"] = {{"gt_frames", metrics.size()},
                       {"psnr", mm::json::number(mean_psnr)},
                       {"ssim", mm::json::number(mean_ssim)},
                       {"covered_psnr", mm::json::number(mean_cov_psnr)},
                       {"coverage", mm::json::number(mean_cov)}};
  }
  json["output"] = output;
  std::cout << mm::json::oneLine(json) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("render_conditioning", run, argc, argv);
}
