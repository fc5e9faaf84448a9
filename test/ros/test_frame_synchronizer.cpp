// RestartableFrameSynchronizer and latestReceipt: sets form from the gated inputs, every message is
// watched first, restart() drops what was queued (also from inside the watch); no master.
#include <gtest/gtest.h>
#include <message_filters/pass_through.h>
#include <sensor_msgs/Image.h>
#include <boost/make_shared.hpp>

#include <vector>

#include "multimodal_nvs/ros/frame_synchronizer.hpp"

namespace mm = multimodal_nvs;
using mm::FrameInput;

namespace {

template <class M>
ros::MessageEvent<const M> event(double stamp, double receipt) {
  auto message = boost::make_shared<M>();
  message->header.stamp = ros::Time(stamp);
  return ros::MessageEvent<const M>(message, ros::Time(receipt));
}

/// Three hand-fed sources behind a RestartableFrameSynchronizer (exact stamps).
struct Harness {
  using Sync = mm::RestartableFrameSynchronizer<sensor_msgs::Image>;
  using Frame = mm::FrameSynchronizer<sensor_msgs::Image>;

  Harness() {
    mm::SyncSettings settings;
    settings.approximate = false;
    sync = std::make_unique<Sync>(
        settings, points, image, info,
        [this](FrameInput input) {
          watched.push_back(input);
          if (restart_on_watch) {
            restart_on_watch = false;
            sync->restart();
          }
        },
        [this](const Frame::PointsEvent& p, const Frame::ImageEvent& i, const Frame::InfoEvent& c) {
          sets.push_back(p.getMessage()->header.stamp.toSec());
          receipts.push_back(mm::latestReceipt(p, i, c).toSec());
        });
  }

  void feed(double stamp, double receipt = 0.0) {
    points.add(event<sensor_msgs::PointCloud2>(stamp, receipt));
    image.add(event<sensor_msgs::Image>(stamp, receipt + 2.0));
    info.add(event<sensor_msgs::CameraInfo>(stamp, receipt + 1.0));
  }

  message_filters::PassThrough<sensor_msgs::PointCloud2> points;
  message_filters::PassThrough<sensor_msgs::Image> image;
  message_filters::PassThrough<sensor_msgs::CameraInfo> info;
  std::vector<FrameInput> watched;
  std::vector<double> sets, receipts;
  bool restart_on_watch = false;
  std::unique_ptr<Sync> sync;
};

TEST(RestartableFrameSynchronizer, WatchesEveryMessageBeforeItFormsASet) {
  Harness h;
  h.feed(1.0, 10.0);
  EXPECT_EQ(h.watched, (std::vector<FrameInput>{FrameInput::kPoints, FrameInput::kImage,
                                                FrameInput::kCameraInfo}));
  EXPECT_EQ(h.sets, std::vector<double>{1.0});
  EXPECT_EQ(h.receipts, std::vector<double>{12.0});  // the image arrived last
}

TEST(RestartableFrameSynchronizer, RestartDropsTheQueuedMessages) {
  Harness h;
  h.points.add(event<sensor_msgs::PointCloud2>(2.0, 0.0));
  h.image.add(event<sensor_msgs::Image>(2.0, 0.0));
  h.sync->restart();
  h.info.add(event<sensor_msgs::CameraInfo>(2.0, 0.0));
  EXPECT_TRUE(h.sets.empty());
  h.points.add(event<sensor_msgs::PointCloud2>(2.0, 0.0));
  h.image.add(event<sensor_msgs::Image>(2.0, 0.0));  // pairs with the info received after restart
  EXPECT_EQ(h.sets, std::vector<double>{2.0});
}

TEST(RestartableFrameSynchronizer, RestartFromInsideTheWatchKeepsTheWatchedMessage) {
  Harness h;
  h.points.add(event<sensor_msgs::PointCloud2>(3.0, 0.0));
  h.image.add(event<sensor_msgs::Image>(3.0, 0.0));
  h.restart_on_watch = true;  // as a node does when the clock jumps back
  h.info.add(event<sensor_msgs::CameraInfo>(3.0, 0.0));
  EXPECT_TRUE(h.sets.empty());
  h.points.add(event<sensor_msgs::PointCloud2>(3.0, 0.0));
  h.image.add(event<sensor_msgs::Image>(3.0, 0.0));
  EXPECT_EQ(h.sets, std::vector<double>{3.0});
}

TEST(RestartableFrameSynchronizer, DisconnectsFromItsSourcesWhenDestroyed) {
  Harness h;
  h.sync.reset();
  h.feed(4.0);
  EXPECT_TRUE(h.watched.empty());
  EXPECT_TRUE(h.sets.empty());
}

}  // namespace
