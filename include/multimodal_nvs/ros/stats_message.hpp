#pragma once
// The depth/stats message of one completed frame. Kept apart from conversions.hpp so that the
// conversions need no generated message (the fuzz build compiles them without catkin).
#include <multimodal_nvs/DepthCompletionStats.h>
#include <std_msgs/Header.h>

#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

/// depth/stats of one completed frame; `latency_ms` runs from the receipt of the set's last
/// message to publication.
DepthCompletionStatsPtr statsMessage(const DepthMapStats& stats, const std_msgs::Header& header,
                                     double latency_ms);

}  // namespace ros_conversions
}  // namespace multimodal_nvs
