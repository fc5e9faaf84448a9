#include "multimodal_nvs/ros/stats_message.hpp"

#include <boost/make_shared.hpp>

#include "multimodal_nvs/core/depth/ground_prior.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

DepthCompletionStatsPtr statsMessage(const DepthMapStats& stats, const std_msgs::Header& header,
                                     double latency_ms) {
  auto message = boost::make_shared<DepthCompletionStats>();
  message->header = header;
  message->points_in = unsigned(stats.points_total);
  message->points_in_view = unsigned(stats.points_in_view);
  message->neighbour_sets = unsigned(stats.neighbour_sets);
  message->kept_pixels = unsigned(stats.kept);
  message->compute_ms = static_cast<float>(stats.compute_ms);
  message->latency_ms = static_cast<float>(latency_ms);
  message->ground_source = stats.ground_source;
  message->ground_mode = stats.ground_mode;
  message->ground_inlier_fraction = static_cast<float>(stats.ground_inlier_fraction);
  message->ground_scan_line_share = static_cast<float>(stats.ground_scan_line_share);
  message->ground_hidden_returns = static_cast<int>(stats.ground_hidden_returns);
  message->ground_edge_ratio = static_cast<float>(stats.ground_edge_ratio);
  message->ground_single_scan_plane = stats.ground_single_scan_plane;
  message->ground_camera_height = static_cast<float>(stats.ground_camera_height);
  message->ground_pitch_deg = static_cast<float>(stats.ground_pitch_deg);
  message->ground_roll_deg = static_cast<float>(stats.ground_roll_deg);
  message->guided_return_density = static_cast<float>(stats.guided_return_density);
  message->guided_prior_weight = static_cast<float>(stats.guided_prior_weight);
  message->guided_band_top_deg = static_cast<float>(stats.guided_band_top_deg);
  return message;
}

geometry_msgs::PolygonStampedPtr groundPlanePolygon(const DepthMapStats& stats,
                                                    const std_msgs::Header& header) {
  if (!(stats.ground_camera_height > 0.0)) return nullptr;
  // Metres; the half-metre ends keep the edges between the lines of rviz's 1 m road grid (which
  // a level camera's plane would otherwise lay them on, hidden).
  constexpr double kNear = 2.5, kFar = 40.5, kHalfWidth = 9.5;
  const GroundPlane plane = GroundPlane::fromAngles(stats.ground_camera_height,
                                                    stats.ground_pitch_deg, stats.ground_roll_deg);
  auto message = boost::make_shared<geometry_msgs::PolygonStamped>();
  message->header = header;
  for (const Eigen::Vector3d& corner : plane.patchCorners(kNear, kFar, kHalfWidth)) {
    geometry_msgs::Point32 point;
    point.x = static_cast<float>(corner.x());
    point.y = static_cast<float>(corner.y());
    point.z = static_cast<float>(corner.z());
    message->polygon.points.push_back(point);
  }
  return message;
}

}  // namespace ros_conversions
}  // namespace multimodal_nvs
