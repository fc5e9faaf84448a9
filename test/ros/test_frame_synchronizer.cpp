// RestartableFrameSynchronizer and latestReceipt: sets form from the gated inputs, every message is
// watched first, restart() drops what was queued (also from inside the watch); learned period
// bounds publish the same sets without waiting for a later message; InputPeriodBound and the
// settings' checks; no master.
#include <gtest/gtest.h>
#include <message_filters/pass_through.h>
#include <sensor_msgs/Image.h>
#include <boost/make_shared.hpp>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "multimodal_nvs/ros/frame_synchronizer.hpp"
#include "multimodal_nvs/ros/input_period_bound.hpp"

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

TEST(InputPeriodBound, IsAFractionOfTheShortestIntervalOnceEnoughWereSeen) {
  mm::InputPeriodBound period(0.9, 4);
  EXPECT_FALSE(period.observe(1.0));
  EXPECT_FALSE(period.observe(1.1));
  EXPECT_FALSE(period.observe(1.2));
  EXPECT_FALSE(period.observe(1.25));  // three intervals: no bound yet
  EXPECT_EQ(period.bound(), 0.0);
  EXPECT_TRUE(period.observe(1.35));
  EXPECT_NEAR(period.bound(), 0.9 * 0.05, 1e-12);
  EXPECT_FALSE(period.observe(1.45));  // longer: unchanged
  EXPECT_TRUE(period.observe(1.47));   // shorter: the bound follows
  EXPECT_NEAR(period.bound(), 0.9 * 0.02, 1e-9);
}

TEST(InputPeriodBound, RepeatedBackwardAndNonFiniteStampsAreNoInterval) {
  mm::InputPeriodBound period(0.5, 2);
  period.observe(10.0);
  period.observe(10.0);  // repeated
  period.observe(2.0);   // a replayed bag: becomes the last stamp, no interval
  EXPECT_EQ(period.bound(), 0.0);
  period.observe(NAN);
  period.observe(2.1);
  EXPECT_EQ(period.bound(), 0.0);  // one interval only
  EXPECT_TRUE(period.observe(2.3));
  EXPECT_NEAR(period.bound(), 0.05, 1e-12);
}

TEST(InputPeriodBound, FractionZeroNeverGivesABound) {
  mm::InputPeriodBound period(0.0, 1);
  for (int k = 0; k < 10; ++k)
    EXPECT_FALSE(period.observe(0.1 * k));
  EXPECT_EQ(period.bound(), 0.0);
}

TEST(SyncSettings, ProblemsAreNamedAndTheDefaultsHaveNone) {
  EXPECT_EQ(mm::syncSettingsProblem(mm::SyncSettings{}), "");
  mm::SyncSettings bad;
  bad.age_penalty = -0.1;
  EXPECT_NE(mm::syncSettingsProblem(bad).find("sync_age_penalty"), std::string::npos);
  bad = {};
  bad.period_bound_fraction = 1.0;
  EXPECT_NE(mm::syncSettingsProblem(bad).find("sync_period_bound_fraction"), std::string::npos);
  bad = {};
  bad.queue_size = 0;
  bad.max_interval = NAN;
  const std::string both = mm::syncSettingsProblem(bad);
  EXPECT_NE(both.find("queue_size"), std::string::npos);
  EXPECT_NE(both.find("max_interval"), std::string::npos);
}

/// A 10 Hz cloud and a 15 Hz camera (image and camera_info with the image's stamp), each message
/// received at its stamp, through the approximate policy. Records each set's stamps and how long
/// after its last member's arrival it was published.
struct StreamRun {
  std::vector<std::pair<double, double>> sets;  // cloud stamp, image stamp
  std::vector<double> waits;                    // publication minus the latest member's stamp
};

/// restart_at: the synchronizer is restarted before the first message stamped at or after it.
StreamRun runStream(const mm::SyncSettings& settings, double image_phase, double seconds,
                    double restart_at = INFINITY) {
  using Sync = mm::RestartableFrameSynchronizer<sensor_msgs::Image>;
  using Frame = mm::FrameSynchronizer<sensor_msgs::Image>;
  message_filters::PassThrough<sensor_msgs::PointCloud2> points;
  message_filters::PassThrough<sensor_msgs::Image> image;
  message_filters::PassThrough<sensor_msgs::CameraInfo> info;
  StreamRun run;
  double now = 0.0;
  Sync sync(
      settings, points, image, info, [](FrameInput) {},
      [&](const Frame::PointsEvent& p, const Frame::ImageEvent& i, const Frame::InfoEvent&) {
        const double cloud = p.getMessage()->header.stamp.toSec();
        const double picture = i.getMessage()->header.stamp.toSec();
        run.sets.emplace_back(cloud, picture);
        run.waits.push_back(now - std::max(cloud, picture));
      });
  std::vector<std::pair<double, int>> arrivals;  // stamp, 0 cloud / 1 image
  for (int k = 0; 0.1 * k < seconds; ++k)
    arrivals.emplace_back(0.1 * k, 0);
  for (int k = 0; image_phase + k / 15.0 < seconds; ++k)
    arrivals.emplace_back(image_phase + k / 15.0, 1);
  std::sort(arrivals.begin(), arrivals.end());
  for (const auto& [stamp, kind] : arrivals) {
    now = stamp;
    if (stamp >= restart_at) {
      restart_at = INFINITY;
      sync.restart();
    }
    if (kind == 0) {
      points.add(event<sensor_msgs::PointCloud2>(stamp, stamp));
    } else {
      image.add(event<sensor_msgs::Image>(stamp, stamp));
      info.add(event<sensor_msgs::CameraInfo>(stamp, stamp));
    }
  }
  return run;
}

TEST(RestartableFrameSynchronizer, LearnedPeriodsPublishTheSameSetsWithoutWaiting) {
  mm::SyncSettings learned;  // the defaults: bounds at 0.9 of the shortest period
  mm::SyncSettings unbounded;
  unbounded.period_bound_fraction = 0.0;
  const StreamRun fast = runStream(learned, 0.01, 3.0);
  const StreamRun slow = runStream(unbounded, 0.01, 3.0);
  ASSERT_GE(slow.sets.size(), 20u);
  // The proof needs the next message without bounds: sets wait (up to a cloud period).
  EXPECT_GT(*std::max_element(slow.waits.begin(), slow.waits.end()), 0.05);
  // With bounds every set after the first half second (four intervals per input) is proven at
  // its last member's arrival; the pairs are the same.
  ASSERT_GE(fast.sets.size(), slow.sets.size() - 1);
  for (std::size_t k = 0; k < slow.sets.size(); ++k) {
    EXPECT_EQ(fast.sets[k], slow.sets[k]) << "set " << k;
    if (fast.sets[k].first > 0.5) {
      EXPECT_NEAR(fast.waits[k], 0.0, 1e-9) << "set " << k;
    }
  }
}

TEST(RestartableFrameSynchronizer, KeepsTheLearnedPeriodsAcrossARestart) {
  const StreamRun run = runStream(mm::SyncSettings{}, 0.01, 3.0, 1.5);
  int after = 0;
  for (std::size_t k = 0; k < run.sets.size(); ++k) {
    if (run.sets[k].first < 1.6) continue;  // the first set after the restart may lack a partner
    ++after;
    EXPECT_NEAR(run.waits[k], 0.0, 1e-9) << "set " << k;
  }
  EXPECT_GE(after, 10);
}

TEST(RestartableFrameSynchronizer, AHigherAgePenaltyPublishesNearTiesAtOnce) {
  // Images 33 and 34 ms either side of every other cloud: the default penalty waits for the later,
  // closer image; 0.5 takes the earlier one as soon as the cloud arrives.
  mm::SyncSettings patient, eager;
  eager.age_penalty = 0.5;
  const double phase = 0.2 - 0.034 - 2.0 / 15.0;  // an image 34 ms before the cloud at 0.2
  const StreamRun wait = runStream(patient, phase, 3.0);
  const StreamRun now = runStream(eager, phase, 3.0);
  double waited = 0.0;
  for (std::size_t k = 0; k < wait.sets.size(); ++k) {
    if (wait.sets[k].first > 0.5) waited = std::max(waited, wait.waits[k]);
  }
  EXPECT_GT(waited, 0.03);
  for (std::size_t k = 0; k < now.sets.size(); ++k) {
    if (now.sets[k].first > 0.5) {
      EXPECT_NEAR(now.waits[k], 0.0, 1e-9) << "set " << k;
    }
  }
}

}  // namespace
