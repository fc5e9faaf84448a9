// gtest-in-rostest: every malformed input the nodelet must reject, each in an otherwise good set
// with its own stamp, then a good set. The node must publish nothing for the bad sets, count each
// under its own reason in diagnostics, and publish the good set.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <algorithm>
#include <functional>
#include <map>
#include <mutex>
#include <set>

#include "rostest_helpers.hpp"
#include "synthetic_scene.hpp"

namespace ss = synthetic_scene;

namespace {

using ss::InputSet;

/// One malformed input: how to break a good set, and the diagnostics reason it must be counted as.
struct BadCase {
  const char* name;
  const char* reason;
  std::function<void(InputSet&)> breakIt;
};

std::vector<BadCase> badCases() {
  return {
      {"cloud without z", "cloud_missing_field", [](InputSet& s) { s.cloud.fields[2].name = "w"; }},
      {"cloud x as INT32", "cloud_field_datatype",
       [](InputSet& s) { s.cloud.fields[0].datatype = sensor_msgs::PointField::INT32; }},
      {"cloud z offset past point_step", "cloud_field_offset",
       [](InputSet& s) { s.cloud.fields[2].offset = 14; }},
      {"cloud data shorter than width*height*point_step", "cloud_data_too_short",
       [](InputSet& s) { s.cloud.data.resize(s.cloud.data.size() - 1); }},
      {"big-endian cloud", "cloud_big_endian", [](InputSet& s) { s.cloud.is_bigendian = true; }},
      {"empty cloud", "cloud_empty",
       [](InputSet& s) {
         s.cloud.width = 0;
         s.cloud.row_step = 0;
         s.cloud.data.clear();
       }},
      {"cloud of NaN and Inf points", "cloud_no_finite_point",
       [](InputSet& s) {
         for (std::size_t i = 0; i < s.cloud.width; ++i) {
           const float bad = i % 2 ? std::numeric_limits<float>::quiet_NaN()
                                   : std::numeric_limits<float>::infinity();
           std::memcpy(&s.cloud.data[i * s.cloud.point_step + 4 * (i % 3)], &bad, 4);
         }
       }},
      {"image with unsupported encoding", "image_encoding",
       [](InputSet& s) { s.image.encoding = sensor_msgs::image_encodings::YUV422; }},
      {"image with a step too small", "image_step",
       [](InputSet& s) { s.image.step = s.image.width * 3 - 1; }},
      {"image size differs from CameraInfo", "camera_info_size",
       [](InputSet& s) { s.info.width = ss::kWidth / 2; }},
      {"CameraInfo with K all zero", "camera_info_intrinsics",
       [](InputSet& s) { s.info.K.fill(0.0); }},
      {"cloud frame without transform", "transform_unavailable",
       [](InputSet& s) { s.cloud.header.frame_id = "frame_nobody_publishes"; }},
  };
}

class BadInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    depth_sub_ = nh_.subscribe<sensor_msgs::Image>("depth/image", 20,
                                                   [this](const sensor_msgs::ImageConstPtr& msg) {
                                                     std::lock_guard<std::mutex> lock(mutex_);
                                                     output_stamps_.insert(msg->header.stamp);
                                                   });
    diagnostics_sub_ =
        rostest_helpers::subscribeDiagnostics(nh_, {"depth completion"}, mutex_, rejected_);
    static_tf_.sendTransform(ss::sensorToCameraMsg(ros::Time(0)));
  }

  void publish(const InputSet& set) { inputs_.publish(set); }

  bool waitFor(const std::function<bool()>& done, double seconds) {
    return rostest_helpers::waitFor(mutex_, done, seconds);
  }

  ros::NodeHandle nh_;
  ss::InputPublishers inputs_{nh_, 5};
  tf2_ros::StaticTransformBroadcaster static_tf_;
  std::mutex mutex_;
  std::set<ros::Time> output_stamps_;
  std::map<std::string, std::string> rejected_;
  // Last, so destroyed first: a callback still arriving must not write into the members above
  // after they are gone (the spinner threads run until after the tests).
  ros::Subscriber depth_sub_, diagnostics_sub_;
};

TEST_F(BadInputTest, RejectsEachBadInputAndRecovers) {
  // Warm up: repeat a good set until the (lazy) node is subscribed and answering.
  bool answered = false;
  for (int attempt = 0; attempt < 40 && !answered; ++attempt) {
    publish(ss::inputSet(ros::Time::now()));
    answered = waitFor([&] { return !output_stamps_.empty(); }, 1.0);
  }
  ASSERT_TRUE(answered) << "the node never answered a good set";
  ros::WallDuration(1.0).sleep();  // let warm-up sets still in flight drain

  const std::vector<BadCase> cases = badCases();
  std::vector<ros::Time> bad_stamps;
  for (const BadCase& bad : cases) {
    const ros::Time stamp = ros::Time::now();
    InputSet set = ss::inputSet(stamp);
    bad.breakIt(set);
    publish(set);
    bad_stamps.push_back(stamp);
    ros::WallDuration(0.25).sleep();  // > tf_timeout, so sets never overlap in the synchronizer
  }
  const ros::Time good = ros::Time::now();
  publish(ss::inputSet(good));
  EXPECT_TRUE(waitFor([&] { return output_stamps_.count(good) > 0; }, 10.0))
      << "no output for the good set after the bad ones";

  // Diagnostics are reported about every second: wait until every reason has been counted.
  auto counted = [this](const BadCase& bad) {
    auto it = rejected_.find(std::string("rejected ") + bad.reason);
    return it != rejected_.end() && it->second != "0";
  };
  waitFor([&] { return std::all_of(cases.begin(), cases.end(), counted); }, 10.0);
  std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(output_stamps_.count(bad_stamps[i]), 0u) << "output for bad input: " << cases[i].name;
    EXPECT_TRUE(counted(cases[i])) << cases[i].name << " not counted as " << cases[i].reason;
  }
}

}  // namespace

int main(int argc, char** argv) {
  return rostest_helpers::runWithSpinner(argc, argv, "test_depth_bad_input", 1);
}
