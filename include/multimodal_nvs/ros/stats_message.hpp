#pragma once
// The depth/stats and depth/ground_plane messages of one completed frame. Kept apart from
// conversions.hpp so that the conversions need no generated message (the fuzz build compiles them
// without catkin).
#include <geometry_msgs/PolygonStamped.h>
#include <multimodal_nvs/DepthCompletionStats.h>
#include <std_msgs/Header.h>

#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

/// depth/stats of one completed frame; `latency_ms` runs from the receipt of the set's last
/// message to publication.
DepthCompletionStatsPtr statsMessage(const DepthMapStats& stats, const std_msgs::Header& header,
                                     double latency_ms);

/// depth/ground_plane: the road the frame's model assumed (the plane of the stats), as a rectangle
/// 2.5-40.5 m ahead and 9.5 m to either side in the image's frame, for rviz to draw over the cloud:
/// on another vehicle a plane from the parameters shows at once if it is not the road. Null when
/// the model has no ground plane.
geometry_msgs::PolygonStampedPtr groundPlanePolygon(const DepthMapStats& stats,
                                                    const std_msgs::Header& header);

}  // namespace ros_conversions
}  // namespace multimodal_nvs
