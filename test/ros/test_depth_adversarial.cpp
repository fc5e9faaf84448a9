// gtest-in-rostest, beyond the malformed inputs of test_depth_bad_input: adversarial layouts and
// values, huge but valid inputs, duplicated stamps, tf going back and a clock reset as when a bag
// loops. The test owns simulated time (it publishes /clock), so it can move it backwards. For each
// bad input the node must publish nothing for it, count it under its own reason in diagnostics and
// process the next good set; huge valid inputs must be processed, and the node's memory must not
// grow from one round of them to the next.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "rostest_helpers.hpp"
#include "synthetic_scene.hpp"

namespace ss = synthetic_scene;
namespace enc = sensor_msgs::image_encodings;

namespace {

using ss::InputSet;

/// Float32 x, y, z, intensity cloud of `points` (sensor frame), stamped `stamp`.
sensor_msgs::PointCloud2 cloudOf(const std::vector<Eigen::Vector3d>& points, const ros::Time& stamp,
                                 const char* frame = ss::kSensorFrame) {
  sensor_msgs::PointCloud2 msg = ss::cloud(stamp);
  msg.header.frame_id = frame;
  msg.width = points.size();
  msg.row_step = msg.width * msg.point_step;
  msg.data.assign(std::size_t(msg.row_step), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const float values[4] = {float(points[i].x()), float(points[i].y()), float(points[i].z()), 1.f};
    std::memcpy(&msg.data[i * 16], values, sizeof values);
  }
  return msg;
}

/// `count` points on the scene's surfaces at random pixels below the sky, in the sensor frame,
/// written straight into the message (10 million Eigen vectors would double the test's memory).
sensor_msgs::PointCloud2 denseCloud(std::size_t count, const ros::Time& stamp) {
  sensor_msgs::PointCloud2 msg = ss::cloud(stamp);
  msg.width = static_cast<std::uint32_t>(count);
  msg.row_step = msg.width * msg.point_step;
  msg.data.resize(std::size_t(msg.row_step));
  const Eigen::Isometry3d camera_to_sensor = ss::sensorToCamera().inverse();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, ss::kWidth), v(ss::kFirstPointRow, ss::kHeight);
  for (std::size_t i = 0; i < count; ++i) {
    const double pu = u(rng), pv = v(rng), z = ss::analyticDepth(pu, pv);
    const Eigen::Vector3d p = camera_to_sensor * Eigen::Vector3d((pu - ss::kCx) / ss::kFx * z,
                                                                 (pv - ss::kCy) / ss::kFy * z, z);
    const float values[4] = {float(p.x()), float(p.y()), float(p.z()), 1.f};
    std::memcpy(&msg.data[i * 16], values, sizeof values);
  }
  return msg;
}

/// A mono8 image of `width` x `height` with the scene's field of view (K scaled to the size).
void resizeView(InputSet& set, std::uint32_t width, std::uint32_t height) {
  set.image.encoding = enc::MONO8;
  set.image.width = width;
  set.image.height = height;
  set.image.step = width;
  set.image.data.assign(std::size_t(width) * height, 128);
  const double s = double(width) / ss::kWidth;
  set.info.width = width;
  set.info.height = height;
  set.info.K = {ss::kFx * s, 0, width / 2.0, 0, ss::kFy * s, height / 2.0, 0, 0, 1};
  set.info.P = {ss::kFx * s, 0, width / 2.0, 0, 0, ss::kFy * s, height / 2.0, 0, 0, 0, 1, 0};
}

/// Resident memory (MB) of process `pid`, from /proc; -1 when unreadable.
double residentMegabytes(int pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return -1.0;
}

/// Process id of the ROS node `name`, through the master and the node's own getPid API.
int pidOfNode(const std::string& name) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = name;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return -1;
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(std::string(payload), host, port)) return -1;
  XmlRpc::XmlRpcClient client(host.c_str(), int(port), "/");
  XmlRpc::XmlRpcValue pid_args, pid_result;
  pid_args[0] = ros::this_node::getName();
  if (!client.execute("getPid", pid_args, pid_result) || pid_result.size() < 3) return -1;
  return int(pid_result[2]);
}

/// Publishers, subscribers and the simulated clock, shared by every test of the process: a clock
/// per test would restart simulated time (itself a clock reset) and reconnect every topic.
class Harness {
 public:
  Harness() {
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    clock_thread_ = std::thread([this] {
      while (running_) {
        rosgraph_msgs::Clock msg;
        msg.clock = simNow();
        clock_pub_.publish(msg);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    });
    depth_sub_ = nh_.subscribe<sensor_msgs::Image>(
        "depth/image", 5, [this](const sensor_msgs::ImageConstPtr& msg) {
          std::lock_guard<std::mutex> lock(mutex_);
          ++outputs_[msg->header.stamp];
          output_sizes_[msg->header.stamp] = {msg->width, msg->height};
        });
    diagnostics_sub_ =
        rostest_helpers::subscribeDiagnostics(nh_, {"depth completion"}, mutex_, diagnostics_);
    // Wait until this process runs on the published clock (ros::Time is 0 until then).
    for (int i = 0; i < 200 && ros::Time::now().isZero(); ++i)
      ros::WallDuration(0.01).sleep();
    static_tf_.sendTransform(ss::sensorToCameraMsg(simNow()));
  }

  ~Harness() {
    running_ = false;
    clock_thread_.join();
  }

  /// Repeats good sets until the (lazy) node is subscribed and answering.
  bool warmUp() {
    for (int attempt = 0; attempt < 40; ++attempt) {
      if (goodSetProcessed(1.0)) return true;
    }
    return false;
  }

  /// Simulated time: wall time since the start plus an offset that jumpBack() decreases.
  ros::Time simNow() const {
    std::lock_guard<std::mutex> lock(clock_mutex_);
    return ros::Time(1000.0) + ros::Duration((ros::WallTime::now() - start_).toSec()) + offset_;
  }
  void jumpBack(double seconds) {
    std::lock_guard<std::mutex> lock(clock_mutex_);
    offset_ -= ros::Duration(seconds);
  }

  void publish(const InputSet& set) { inputs_.publish(set); }

  bool waitFor(const std::function<bool()>& done, double seconds) {
    return rostest_helpers::waitFor(mutex_, done, seconds);
  }

  /// Publishes a good set now and waits for its depth image.
  bool goodSetProcessed(double seconds = 10.0) {
    const ros::Time stamp = simNow();
    publish(ss::inputSet(stamp));
    return waitFor([&] { return outputs_.count(stamp) > 0; }, seconds);
  }

  /// A diagnostics value of the depth nodelet as a number (-1 while not reported).
  double diagnostic(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = diagnostics_.find(key);
    return it == diagnostics_.end() ? -1.0 : std::stod(it->second);
  }
  /// Waits until the diagnostics report `key` >= `at_least` (they are published about once a s).
  bool diagnosticReaches(const std::string& key, double at_least, double seconds = 5.0) {
    return waitFor(
        [&] {
          auto it = diagnostics_.find(key);
          return it != diagnostics_.end() && std::stod(it->second) >= at_least;
        },
        seconds);
  }

  ros::NodeHandle nh_;
  ros::Publisher clock_pub_;
  ss::InputPublishers inputs_{nh_, 2};
  tf2_ros::StaticTransformBroadcaster static_tf_;
  tf2_ros::TransformBroadcaster tf_;
  mutable std::mutex clock_mutex_;
  const ros::WallTime start_ = ros::WallTime::now();
  ros::Duration offset_;
  std::atomic<bool> running_{true};
  std::thread clock_thread_;
  std::mutex mutex_;
  std::map<ros::Time, int> outputs_;
  std::map<ros::Time, std::pair<std::uint32_t, std::uint32_t>> output_sizes_;
  std::map<std::string, std::string> diagnostics_;
  // Last, so destroyed first: a callback still arriving must not write into the members above
  // after they are gone (the spinner threads run until after the tests).
  ros::Subscriber depth_sub_, diagnostics_sub_;
};

std::unique_ptr<Harness> g_harness;  // created in main, after ros::init

class AdversarialTest : public ::testing::Test {
 protected:
  Harness& h = *g_harness;
};

/// One adversarial input: how to break a good set (stamped `stamp`), and its diagnostics reason.
struct BadCase {
  const char* name;
  const char* reason;
  std::function<void(InputSet&)> breakIt;
};

std::vector<BadCase> badCases() {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  return {
      {"point_step smaller than its fields", "cloud_field_offset",
       [](InputSet& s) {
         s.cloud.point_step = 8;
         s.cloud.row_step = s.cloud.width * 8;
       }},
      {"x offset far beyond point_step (wraps in 32 bits)", "cloud_field_offset",
       [](InputSet& s) { s.cloud.fields[0].offset = 0xFFFFFFFE; }},
      {"row_step smaller than width * point_step", "cloud_layout",
       [](InputSet& s) { s.cloud.row_step = s.cloud.width * s.cloud.point_step - 4; }},
      {"row_step larger than the data", "cloud_data_too_short",
       [](InputSet& s) { s.cloud.row_step *= 2; }},
      {"width * height overflowing 32 bits", "cloud_data_too_short",
       [](InputSet& s) {
         s.cloud.width = 0x10000;
         s.cloud.height = 0x10001;
         s.cloud.row_step = s.cloud.width * s.cloud.point_step;
       }},
      {"width * point_step overflowing row_step", "cloud_layout",
       [](InputSet& s) {
         s.cloud.width = 0x80000000u;
         s.cloud.height = 0x80000000u;
         s.cloud.row_step = 0xFFFFFFFFu;
       }},
      {"all points NaN", "cloud_no_finite_point",
       [nan](InputSet& s) {
         for (std::size_t i = 0; i < s.cloud.width; ++i) {
           for (int axis = 0; axis < 3; ++axis)
             std::memcpy(&s.cloud.data[i * s.cloud.point_step + 4 * axis], &nan, 4);
         }
       }},
      {"all points behind the camera", "cloud_behind_camera",
       [](InputSet& s) {
         // The scene mirrored through the camera: every depth negated.
         const Eigen::Isometry3d to_camera = ss::sensorToCamera();
         std::vector<Eigen::Vector3d> points = ss::sensorPoints();
         for (auto& p : points) {
           Eigen::Vector3d c = to_camera * p;
           c.z() = -c.z();
           p = to_camera.inverse() * c;
         }
         s.cloud = cloudOf(points, s.cloud.header.stamp);
       }},
      {"CameraInfo with NaN in K", "camera_info_intrinsics",
       [](InputSet& s) { s.info.K[4] = std::numeric_limits<double>::quiet_NaN(); }},
      {"CameraInfo with a negative focal length", "camera_info_intrinsics",
       [](InputSet& s) { s.info.K[0] = -ss::kFx; }},
      {"CameraInfo of size 0", "camera_info_size",
       [](InputSet& s) {
         s.info.width = 0;
         s.info.height = 0;
       }},
      {"CameraInfo of negative size (-1 as uint32)", "camera_info_size",
       [](InputSet& s) { s.info.height = 0xFFFFFFFFu; }},
      {"image 0x0", "image_empty",
       [](InputSet& s) {
         s.image.width = s.image.height = s.image.step = 0;
         s.image.data.clear();
       }},
      {"image of negative width (-1 as uint32)", "image_step",
       [](InputSet& s) { s.image.width = 0xFFFFFFFFu; }},
  };
}

TEST_F(AdversarialTest, EachAdversarialInputIsRejectedAndTheNextGoodSetProcessed) {
  ASSERT_TRUE(h.warmUp()) << "the node never answered a good set";

  for (const BadCase& bad : badCases()) {
    const ros::Time stamp = h.simNow();
    InputSet set = ss::inputSet(stamp);
    bad.breakIt(set);
    h.publish(set);
    ros::WallDuration(0.25).sleep();  // > tf_timeout, so sets never overlap in the synchronizer
    EXPECT_TRUE(h.goodSetProcessed()) << "no output for the good set after: " << bad.name;
    std::lock_guard<std::mutex> lock(h.mutex_);
    EXPECT_EQ(h.outputs_.count(stamp), 0u) << "output for bad input: " << bad.name;
  }
  for (const BadCase& bad : badCases()) {
    EXPECT_TRUE(h.diagnosticReaches(std::string("rejected ") + bad.reason, 1))
        << bad.name << " not counted as " << bad.reason;
  }
}

TEST_F(AdversarialTest, DuplicateAndOutOfOrderStampsAreDropped) {
  ASSERT_TRUE(h.warmUp());
  const ros::Time first = h.simNow();
  h.publish(ss::inputSet(first));
  ASSERT_TRUE(h.waitFor([&] { return h.outputs_.count(first) > 0; }, 10.0));
  ros::WallDuration(0.2).sleep();
  h.publish(ss::inputSet(first));  // the same stamps again
  ros::WallDuration(0.2).sleep();
  h.publish(ss::inputSet(first - ros::Duration(0.1)));  // a little older: out of order
  ros::WallDuration(0.25).sleep();
  EXPECT_TRUE(h.goodSetProcessed()) << "no output after the duplicate";
  // The out-of-order set may already be dropped by the synchronizer (it pairs in stamp order).
  EXPECT_TRUE(h.diagnosticReaches("rejected stamp_not_newer", 1));
  std::lock_guard<std::mutex> lock(h.mutex_);
  EXPECT_EQ(h.outputs_[first], 1) << "the duplicated set was published twice";
  EXPECT_EQ(h.outputs_.count(first - ros::Duration(0.1)), 0u);
}

TEST_F(AdversarialTest, TfGoingBackIsATransformErrorNotACrash) {
  ASSERT_TRUE(h.warmUp());
  // A moving sensor frame on /tf: processed while its transforms are current.
  auto moving = [](const ros::Time& stamp) {
    geometry_msgs::TransformStamped t = ss::sensorToCameraMsg(stamp);
    t.child_frame_id = "moving_radar";
    return t;
  };
  const ros::Time now = h.simNow();
  h.tf_.sendTransform(moving(now));
  ros::WallDuration(0.1).sleep();
  InputSet set = ss::inputSet(now);
  set.cloud.header.frame_id = "moving_radar";
  h.publish(set);
  ASSERT_TRUE(h.waitFor([&] { return h.outputs_.count(now) > 0; }, 10.0)) << "dynamic tf not used";
  // Then its tf jumps 30 s back (older than tf's 10 s cache): tf2 ignores it, the lookup fails.
  const ros::Time past = now - ros::Duration(30.0);
  h.tf_.sendTransform(moving(past));
  ros::WallDuration(0.1).sleep();
  set = ss::inputSet(past);
  set.cloud.header.frame_id = "moving_radar";
  h.publish(set);
  EXPECT_TRUE(h.diagnosticReaches("rejected transform_unavailable", 1));
  EXPECT_TRUE(h.goodSetProcessed()) << "no output after tf went back";
  std::lock_guard<std::mutex> lock(h.mutex_);
  EXPECT_EQ(h.outputs_.count(past), 0u);
}

TEST_F(AdversarialTest, ClockResetStartsOverWithoutLosingStaticTf) {
  ASSERT_TRUE(h.warmUp());
  const double jumps_before = h.diagnostic("time jumps back");
  // An image and CameraInfo that never find their cloud wait in the synchronizer when the clock
  // goes back; they must not be paired with the restarted stream's first cloud.
  const InputSet stale = ss::inputSet(h.simNow());
  h.inputs_.publishWithoutCloud(stale);
  ros::WallDuration(0.1).sleep();
  h.jumpBack(100.0);  // as a bag played in a loop with --clock
  ros::WallDuration(0.2).sleep();
  // The restarted stream (stamps 100 s before the last processed set) is processed, with the
  // extrinsic from /tf_static that was published once, before the reset.
  EXPECT_TRUE(h.goodSetProcessed()) << "no output after the clock reset";
  EXPECT_TRUE(h.goodSetProcessed()) << "no output for the second set after the clock reset";
  EXPECT_TRUE(h.diagnosticReaches("time jumps back", std::max(1.0, jumps_before + 1)));
  std::lock_guard<std::mutex> lock(h.mutex_);
  EXPECT_EQ(h.outputs_.count(stale.image.header.stamp), 0u);
}

TEST_F(AdversarialTest, HugeValidInputsAreProcessedInBoundedMemory) {
  ASSERT_TRUE(h.warmUp());
  std::string process_node;
  ASSERT_TRUE(ros::param::get("~process_node", process_node));
  const int pid = pidOfNode(process_node);
  ASSERT_GT(pid, 0) << "no pid for " << process_node;
  std::vector<double> rss;
  for (int round = 0; round < 2; ++round) {
    {  // 10 million points (160 MB): read every k-th, processed
      const ros::Time stamp = h.simNow();
      InputSet set = ss::inputSet(stamp);
      set.cloud = denseCloud(10 * 1000 * 1000, stamp);
      h.publish(set);
      EXPECT_TRUE(h.waitFor([&] { return h.outputs_.count(stamp) > 0; }, 60.0))
          << "no output for 10 million points (round " << round << ")";
    }
    {  // 8000 x 8000 image with its CameraInfo: a 4000 x 4000 depth map
      const ros::Time stamp = h.simNow();
      InputSet set = ss::inputSet(stamp);
      resizeView(set, 8000, 8000);
      h.publish(set);
      EXPECT_TRUE(h.waitFor([&] { return h.outputs_.count(stamp) > 0; }, 90.0))
          << "no output for 8000x8000 (round " << round << ")";
      std::lock_guard<std::mutex> lock(h.mutex_);
      EXPECT_EQ(h.output_sizes_[stamp].first, 4000u);  // stride 2 (adversarial_params.yaml)
    }
    {  // 1 x 1 image
      const ros::Time stamp = h.simNow();
      InputSet set = ss::inputSet(stamp);
      resizeView(set, 1, 1);
      h.publish(set);
      EXPECT_TRUE(h.waitFor([&] { return h.outputs_.count(stamp) > 0; }, 10.0))
          << "no output for a 1x1 image (round " << round << ")";
    }
    EXPECT_TRUE(h.goodSetProcessed()) << "no output for a normal set after the huge ones";
    rss.push_back(residentMegabytes(pid));
  }
  EXPECT_TRUE(h.diagnosticReaches("subsampled clouds", 2));
  std::printf("[ adversarial ] %s (pid %d) RSS after round 1: %.0f MB, after round 2: %.0f MB\n",
              process_node.c_str(), pid, rss[0], rss[1]);
  // Bounded: the second round reuses what the first one left, it does not add to it.
  EXPECT_LT(rss[1] - rss[0], 64.0) << "RSS grew from " << rss[0] << " to " << rss[1] << " MB";
}

}  // namespace

int main(int argc, char** argv) {
  return rostest_helpers::runWithSpinner(argc, argv, "test_depth_adversarial", 2, [] {
    g_harness = std::make_unique<Harness>();
    const int result = RUN_ALL_TESTS();
    g_harness.reset();
    return result;
  });
}
