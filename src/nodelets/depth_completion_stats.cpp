#include "depth_completion_stats.hpp"

#include <multimodal_nvs/DepthCompletionStats.h>
#include <boost/make_shared.hpp>

namespace multimodal_nvs {

ros::Publisher advertiseStats(ros::NodeHandle& nh, const std::string& topic,
                              const ros::SubscriberStatusCallback& connect_cb) {
  return nh.advertise<DepthCompletionStats>(topic, 5, connect_cb, connect_cb);
}

void publishStats(const ros::Publisher& publisher, const std_msgs::Header& header,
                  const FrameStatsFields& fields) {
  auto stats = boost::make_shared<DepthCompletionStats>();
  stats->header = header;
  stats->points_in = fields.points_in;
  stats->points_in_view = fields.points_in_view;
  stats->neighbour_sets = fields.neighbour_sets;
  stats->kept_pixels = fields.kept_pixels;
  stats->compute_ms = static_cast<float>(fields.compute_ms);
  stats->latency_ms = static_cast<float>(fields.latency_ms);
  publisher.publish(stats);
}

}  // namespace multimodal_nvs
