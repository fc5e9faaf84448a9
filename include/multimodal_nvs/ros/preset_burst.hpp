#pragma once
// The conditioning renderer's preset mode: the preset trajectory from the keyframe rendered as one
// burst, its frames stamped for publishing and, with export_dir, written as a GEN3C folder.
#include <ros/time.h>
#include <std_msgs/Header.h>

#include <functional>
#include <string>

#include "multimodal_nvs/core/render/render_burst.hpp"
#include "multimodal_nvs/ros/renderer_keyframe.hpp"

namespace multimodal_nvs {

/// The settings alone need the inputs (an exported preset renders with no output subscriber).
bool presetExportWanted(const ConditioningRendererSettings& settings);

/// EXPORT_DIR/<sec>_<nsec> (10 and 9 digits): one GEN3C folder per keyframe.
std::string gen3cExportFolder(const std::string& export_dir, const ros::Time& keyframe_stamp);

/// Frame `index` of a burst is stamped keyframe stamp + index / frame_rate.
ros::Time burstFrameStamp(const ros::Time& keyframe_stamp, int index, double frame_rate);

/// Why there is no burst to render: no keyframe yet, or one with no point.
std::string burstUnavailableReason(bool have_keyframe);

/// "rendered N frames at HxW (PRESET MAGNITUDE UNIT, SPLAT) in T ms[; GEN3C folder F]".
std::string burstReport(const ConditioningRendererSettings& settings, double burst_ms,
                        const std::string& gen3c_folder);

/// One rendered frame of a burst with its target camera and header (the keyframe's, restamped).
using BurstPublisher = std::function<void(const RenderedFrame& frame, const TargetCamera& camera,
                                          const std_msgs::Header& header)>;

struct PresetBurstResult {
  bool ok = false;
  std::string gen3c_folder;  ///< where the export went; empty without export_dir
  std::string error;         ///< why the burst failed, when !ok
  Trajectory trajectory;     ///< the rendered views, when ok
};

/// Renders settings.preset from `keyframe` (its `cloud` for the settings), hands every frame in
/// order to `publish` and, with export_dir, writes the GEN3C folder gen3cExportFolder(export_dir,
/// keyframe stamp) under a temporary name renamed when complete; `warn` gets gen3cSizeWarning's
/// text first when that export is not GEN3C's size. A bad trajectory or a failed export is the
/// result's error; exceptions of `publish` propagate.
PresetBurstResult renderPresetBurst(PointSplatter& splatter, const RendererKeyframe& keyframe,
                                    const ColoredCloud& cloud,
                                    const ConditioningRendererSettings& settings,
                                    const BurstPublisher& publish,
                                    const std::function<void(const std::string&)>& warn);

}  // namespace multimodal_nvs
