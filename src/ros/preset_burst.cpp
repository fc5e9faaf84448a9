#include "multimodal_nvs/ros/preset_burst.hpp"

#include <cstdio>
#include <filesystem>
#include <optional>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

bool presetExportWanted(const ConditioningRendererSettings& settings) {
  return settings.source == TrajectorySource::kPreset && !settings.export_dir.empty();
}

std::string gen3cExportFolder(const std::string& export_dir, const ros::Time& keyframe_stamp) {
  char name[32];
  std::snprintf(name, sizeof name, "%010u_%09u", keyframe_stamp.sec, keyframe_stamp.nsec);
  return export_dir + "/" + name;
}

ros::Time burstFrameStamp(const ros::Time& keyframe_stamp, int index, double frame_rate) {
  return keyframe_stamp + ros::Duration(index / frame_rate);
}

std::string burstUnavailableReason(bool have_keyframe) {
  return have_keyframe ? "the keyframe has no point to render"
                       : "no keyframe yet (inputs are subscribed only while an output has a "
                         "subscriber or a preset export_dir is set)";
}

std::string burstReport(const ConditioningRendererSettings& settings, double burst_ms,
                        const std::string& gen3c_folder) {
  const ImageSize size = settings.renderSize();
  char text[160];
  std::snprintf(text, sizeof text, "rendered %d frames at %dx%d (%s %g %s, %s) in %.0f ms",
                settings.num_frames, size.height, size.width, toString(settings.preset).c_str(),
                settings.magnitude, magnitudeUnit(settings.preset).c_str(),
                toString(settings.splat.mode).c_str(), burst_ms);
  std::string report = text;
  if (!gen3c_folder.empty()) report += "; GEN3C folder " + gen3c_folder;
  return report;
}

namespace {

/// The burst into `result` (trajectory, folder); throws InputError (trajectory, rendering, export)
/// and filesystem_error (export).
void renderAndExport(PointSplatter& splatter, const RendererKeyframe& keyframe,
                     const ColoredCloud& cloud, const ConditioningRendererSettings& settings,
                     const BurstPublisher& publish,
                     const std::function<void(const std::string&)>& warn,
                     PresetBurstResult& result) {
  const ros_conversions::RendererInput& key = keyframe.input();
  const ImageSize size = settings.renderSize();
  const int n = settings.num_frames;
  result.trajectory =
      presetTrajectory(settings.preset, settings.magnitude, n,
                       key.image_intrinsics.scaledTo(key.image_size.height, key.image_size.width,
                                                     size.height, size.width),
                       size, cloud.medianDepth());
  std::optional<Gen3cBurstExport> gen3c;
  if (!settings.export_dir.empty()) {
    if (const auto warning = gen3cSizeWarning(n, size)) warn(*warning);
    gen3c.emplace(gen3cExportFolder(settings.export_dir, key.header.stamp), key.image_bgr, n, size,
                  Gen3cFolderWrite::kRenameWhenComplete);
  }
  const Trajectory& trajectory = result.trajectory;
  std_msgs::Header header = key.header;
  renderBurst(splatter, cloud, trajectory, settings.splat,
              [&](int index, const RenderedFrame& frame) {
                header.stamp = burstFrameStamp(key.header.stamp, index, settings.burst_frame_rate);
                publish(frame, trajectory.cameras[static_cast<std::size_t>(index)], header);
                if (gen3c) gen3c->append(frame);
              });
  if (!gen3c) return;
  gen3c->finish();
  result.gen3c_folder = gen3c->folder();
}

}  // namespace

PresetBurstResult renderPresetBurst(PointSplatter& splatter, const RendererKeyframe& keyframe,
                                    const ColoredCloud& cloud,
                                    const ConditioningRendererSettings& settings,
                                    const BurstPublisher& publish,
                                    const std::function<void(const std::string&)>& warn) {
  PresetBurstResult result;
  try {
    renderAndExport(splatter, keyframe, cloud, settings, publish, warn, result);
    result.ok = true;
  } catch (const InputError& e) {
    result.error = std::string("preset burst failed: ") + e.what();
  } catch (const std::filesystem::filesystem_error& e) {
    result.error = std::string("GEN3C export failed: ") + e.what();
  }
  return result;
}

}  // namespace multimodal_nvs
