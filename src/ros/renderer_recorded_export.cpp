#include "multimodal_nvs/ros/renderer_recorded_export.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <utility>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/eval/nvs_metrics.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/render/burst_pipeline.hpp"
#include "multimodal_nvs/core/render/preview.hpp"
#include "multimodal_nvs/core/render/render_burst.hpp"
#include "multimodal_nvs/ros/preset_burst.hpp"

namespace multimodal_nvs {

namespace fs = std::filesystem;

std::optional<std::string> recordedExportRequestError(const RecordedExportRequest& request) {
  if (request.output_dir.empty()) return "no output directory (goal output_dir or export_dir)";
  if (request.duration < 0.0) return "duration must be >= 0";
  if (request.duration == 0.0 && request.num_poses < 1) {
    return "give num_poses >= 1 or a duration > 0";
  }
  if (request.num_frames < 1) return "num_frames must be >= 1";
  if (request.duration == 0.0 && request.num_poses > request.num_frames) {
    return "num_poses (" + std::to_string(request.num_poses) + ") exceeds num_frames (" +
           std::to_string(request.num_frames) + ")";
  }
  return std::nullopt;
}

// ---- Collector

void RecordedPoseCollector::start(const RecordedExportRequest& request,
                                  const std::optional<ros::Time>& latest_seen) {
  poses_ = RecordedPoses{};
  poses_.request = request;
  not_after_ = latest_seen;
  abort_reason_.clear();
  stage_ = Stage::kWaitingForKeyframe;
}

bool RecordedPoseCollector::acceptsKeyframe(const ros::Time& stamp) const {
  return stage_ == Stage::kWaitingForKeyframe && (!not_after_ || stamp > *not_after_);
}

void RecordedPoseCollector::keyframe(const ros::Time& stamp, const Eigen::Matrix4d& camera_to_world,
                                     const cv::Mat& ground_truth) {
  if (!acceptsKeyframe(stamp)) return;
  stage_ = Stage::kCollecting;
  cameraFrame(stamp, camera_to_world, ground_truth);
}

void RecordedPoseCollector::cameraFrame(const ros::Time& stamp,
                                        const Eigen::Matrix4d& camera_to_world,
                                        const cv::Mat& ground_truth) {
  if (stage_ != Stage::kCollecting) return;
  const RecordedExportRequest& request = poses_.request;
  if (!poses_.stamps.empty()) {
    if (stamp < poses_.stamps.back()) {
      char reason[160];
      std::snprintf(reason, sizeof reason,
                    "camera time went back from %.3f to %.3f s while collecting the recorded "
                    "trajectory (a bag loop or a restarted stream)",
                    poses_.stamps.back().toSec(), stamp.toSec());
      abort(reason);
      return;
    }
    if (stamp == poses_.stamps.back()) return;  // the keyframe's own image, or a duplicate
    if (request.duration > 0.0 && (stamp - poses_.stamps.front()).toSec() > request.duration) {
      stage_ = Stage::kComplete;
      return;
    }
  }
  poses_.stamps.push_back(stamp);
  poses_.camera_to_world.push_back(camera_to_world);
  poses_.ground_truth.push_back(ground_truth);
  const int limit = request.duration > 0.0 ? request.num_frames : request.num_poses;
  if (collected() >= limit) stage_ = Stage::kComplete;
}

void RecordedPoseCollector::abort(const std::string& reason) {
  if (!active()) return;
  abort_reason_ = reason;
  stage_ = Stage::kAborted;
}

RecordedPoses RecordedPoseCollector::take() {
  RecordedPoses out = std::move(poses_);
  reset();
  return out;
}

void RecordedPoseCollector::reset() {
  poses_ = RecordedPoses{};
  abort_reason_.clear();
  not_after_.reset();
  stage_ = Stage::kIdle;
}

std::string recordedPoseKey(const std::string& world_frame) {
  return world_frame + "ToCamera";
}

// ---- Export

namespace {

struct ExportCancelled {};

/// A double as command-line text that reads back to the same value (17 significant digits).
std::string exactNumber(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

/// A pose in the VoD pose-file format; nlohmann prints each double in its shortest form that
/// reads back to the same value, so render_conditioning renders exactly the recorded pose.
std::string poseJson(const std::string& key, const Eigen::Matrix4d& pose) {
  json::Json values = json::Json::array();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c)
      values.push_back(pose(r, c));
  }
  return json::oneLine(json::Json{{key, values}}) + "\n";
}

std::string poseFileName(int index) {
  char name[16];
  std::snprintf(name, sizeof name, "%03d.json", index);
  return name;
}

/// keyframe/: what render_conditioning needs to render the same frames, and the command.
void writeKeyframeInputs(const std::string& dir, const RecordedExportJob& job) {
  const ros_conversions::RendererInput& key = job.keyframe;
  makeDirectories(dir + "/poses");
  if (!cv::imwrite(dir + "/image.png", key.image_bgr)) {
    throw InputError(dir + "/image.png: cannot write");
  }
  const std::vector<std::size_t> grid{std::size_t(key.grid_size.height),
                                      std::size_t(key.grid_size.width)};
  const cv::Mat depth = key.depth.isContinuous() ? key.depth : key.depth.clone();
  const cv::Mat kept = key.kept.isContinuous() ? key.kept : key.kept.clone();
  io::writeNpy(dir + "/depth.npy", depth.ptr<float>(0), grid);
  io::writeNpy(dir + "/valid.npy", kept.ptr<std::uint8_t>(0), grid);
  const std::string pose_key = recordedPoseKey(job.settings.world_frame);
  std::string poses;
  for (std::size_t j = 0; j < job.poses.camera_to_world.size(); ++j) {
    const std::string name = "poses/" + poseFileName(static_cast<int>(j));
    json::writeTextFile(dir + "/" + name, poseJson(pose_key, job.poses.camera_to_world[j]));
    poses += " keyframe/" + name;
  }
  const PinholeIntrinsics& k = key.image_intrinsics;
  const ImageSize size = job.settings.renderSize();
  const BackprojectionParams& prep = job.backprojection;
  std::ostringstream command;
  command << "# From the export folder; reproduces gen3c/ byte for byte.\n"
          << "render_conditioning --image keyframe/image.png --depth keyframe/depth.npy"
          << " --valid keyframe/valid.npy --intrinsics " << exactNumber(k.fx) << " "
          << exactNumber(k.fy) << " " << exactNumber(k.cx) << " " << exactNumber(k.cy) << " --poses"
          << poses << " --pose-key " << pose_key << " --num-frames " << job.poses.request.num_frames
          << " --size " << size.height << " " << size.width << " --splat "
          << toString(job.settings.splat.mode) << " --resize-depth "
          << (prep.resize_to_render ? "yes" : "no") << " --max-depth "
          << exactNumber(prep.max_depth) << " --edge-threshold " << exactNumber(prep.edge_threshold)
          << " --gen3c --output OUTPUT\n";
  json::writeTextFile(dir + "/render_conditioning.txt", command.str());
}

std::string groundTruthName(const std_msgs::Header& keyframe_header, const ros::Time& stamp) {
  char name[96];
  std::snprintf(name, sizeof name, "camera image %u.%09u", stamp.sec, stamp.nsec);
  return keyframe_header.frame_id + " " + name;
}

/// Renders and writes everything into `dir`; throws InputError, filesystem_error or
/// ExportCancelled.
Trajectory renderInto(const std::string& dir, PointSplatter& splatter, const RecordedExportJob& job,
                      const std::function<void(int, int)>& progress,
                      const std::function<bool()>& cancelled) {
  const ros_conversions::RendererInput& key = job.keyframe;
  const ImageSize size = job.settings.renderSize();
  const int num_frames = job.poses.request.num_frames;
  const Trajectory trajectory =
      recordedTrajectory(job.poses.camera_to_world, num_frames,
                         key.image_intrinsics.scaledTo(key.image_size.height, key.image_size.width,
                                                       size.height, size.width),
                         size);
  writeKeyframeInputs(dir + "/keyframe", job);
  std::vector<int> pose_of_frame(static_cast<std::size_t>(num_frames), -1);
  for (std::size_t j = 0; j < trajectory.recorded_frames.size(); ++j) {
    pose_of_frame[static_cast<std::size_t>(trajectory.recorded_frames[j])] = static_cast<int>(j);
  }
  Gen3cBurstExport gen3c(dir + "/gen3c", key.image_bgr, num_frames, size,
                         Gen3cFolderWrite::kInPlace);
  std::vector<NvsFrameMetrics> metrics, metrics_of_frame(static_cast<std::size_t>(num_frames));
  std::vector<char> has_metrics(static_cast<std::size_t>(num_frames), 0);
  if (cancelled()) throw ExportCancelled{};
  // The arrays (each frame has its own place in them) and the metrics (preview fill, SSIM) on
  // worker threads while the next chunk renders; the progress in frame order.
  BurstFrameStages stages;
  stages.parallel = [&](int index, RenderedFrame& frame, int) {
    gen3c.write(index, frame);
    const auto i = static_cast<std::size_t>(index);
    const int pose = pose_of_frame[i];
    if (pose < 0) return;
    const cv::Mat& gt = job.poses.ground_truth[static_cast<std::size_t>(pose)];
    if (gt.empty()) return;
    metrics_of_frame[i] = nvsFrameMetrics(
        index, groundTruthName(key.header, job.poses.stamps[static_cast<std::size_t>(pose)]), frame,
        fillHolesPushPull(frame.bgr, frame.mask), gt);
    has_metrics[i] = 1;
  };
  stages.ordered = [&](int index, RenderedFrame&) {
    const auto i = static_cast<std::size_t>(index);
    if (has_metrics[i] != 0) metrics.push_back(metrics_of_frame[i]);
    progress(index + 1, num_frames);
    if (cancelled()) throw ExportCancelled{};
  };
  BurstPipelineOptions pipeline;
  pipeline.workers = splatter.threads();
  renderBurstPipelined(splatter, job.cloud, trajectory, job.settings.splat, stages, pipeline);
  gen3c.finish();
  json::writeTextFile(dir + "/metrics.json",
                      nvsMetricsJson(metrics, toString(job.settings.splat.mode)));
  return trajectory;
}

}  // namespace

RecordedExportResult exportRecordedTrajectory(PointSplatter& splatter, const RecordedExportJob& job,
                                              const std::function<void(int, int)>& progress,
                                              const std::function<bool()>& cancelled) {
  RecordedExportResult result;
  const std::string folder =
      gen3cExportFolder(job.poses.request.output_dir, job.keyframe.header.stamp);
  const std::string partial = folder + ".partial";
  std::error_code ignored;
  try {
    fs::remove_all(partial);
    makeDirectories(partial);
    result.trajectory = renderInto(partial, splatter, job, progress, cancelled);
    fs::remove_all(folder);
    fs::rename(partial, folder);
    result.ok = true;
    result.folder = folder;
    return result;
  } catch (const ExportCancelled&) {
    result.cancelled = true;
    result.error = "export cancelled while rendering; " + partial + " removed";
  } catch (const InputError& e) {
    result.error = std::string("recorded export failed: ") + e.what();
  } catch (const fs::filesystem_error& e) {
    result.error = std::string("recorded export failed: ") + e.what();
  }
  fs::remove_all(partial, ignored);
  return result;
}

}  // namespace multimodal_nvs
