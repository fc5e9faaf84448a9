#include "multimodal_nvs/ros/stats_message.hpp"

#include <boost/make_shared.hpp>

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
  message->ground_camera_height = static_cast<float>(stats.ground_camera_height);
  message->ground_pitch_deg = static_cast<float>(stats.ground_pitch_deg);
  message->ground_roll_deg = static_cast<float>(stats.ground_roll_deg);
  return message;
}

}  // namespace ros_conversions
}  // namespace multimodal_nvs
