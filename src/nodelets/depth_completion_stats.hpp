#pragma once
// depth/stats publishing, kept in its own translation unit: the generated message
// multimodal_nvs::DepthCompletionStats and the core's struct of the same name cannot be visible
// together (see the note in the nodelet).
#include <ros/ros.h>
#include <std_msgs/Header.h>

namespace multimodal_nvs {

struct FrameStatsFields {
  unsigned points_in = 0;
  unsigned points_in_view = 0;
  unsigned neighbour_sets = 0;
  unsigned kept_pixels = 0;
  double compute_ms = 0.0;
  double latency_ms = 0.0;
};

ros::Publisher advertiseStats(ros::NodeHandle& nh, const std::string& topic,
                              const ros::SubscriberStatusCallback& connect_cb);
void publishStats(const ros::Publisher& publisher, const std_msgs::Header& header,
                  const FrameStatsFields& fields);

}  // namespace multimodal_nvs
