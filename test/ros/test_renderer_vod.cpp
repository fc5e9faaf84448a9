// gtest-in-rostest: the paper's experiment through launch/pipeline.launch on real data. The VoD
// 08350-08365 bag (vod_to_bag at run time: 16 camera images and odom poses at 10 Hz, one radar
// scan at 08350) is played once a recorded-trajectory export is waiting for its keyframe:
//   - tf mode renders the one keyframe into all 16 camera poses (conditioning/image per image);
//   - ~export_trajectory collects the 16 poses, resamples them to 121 frames and writes the
//     export, whose GEN3C arrays equal byte for byte what render_conditioning writes from the
//     export's keyframe/ (image, depth, kept mask, poses) with the command the export records;
//     the recorded poses are VoD's own (through tf), and metrics.json has the 16 recorded frames;
//   - a second goal cancelled while it waits for a keyframe ends preempted, leaves no folder, and
//     is counted in the diagnostics.
#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <multimodal_nvs/ExportTrajectoryAction.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/Image.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../test_data.hpp"
#include "child_processes.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "rostest_helpers.hpp"

#ifndef MMNVS_TOOL_DIR
#error "MMNVS_TOOL_DIR must point at the devel space's lib/multimodal_nvs"
#endif

namespace fs = std::filesystem;
namespace mm = multimodal_nvs;
using Client = actionlib::SimpleActionClient<multimodal_nvs::ExportTrajectoryAction>;
using State = actionlib::SimpleClientGoalState;

namespace {

constexpr int kFirstFrame = 8350, kPoses = 16;

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

/// Polls `done` every 50 ms for `seconds` of wall time (the bag's clock stops when it ends).
bool waitWall(const std::function<bool()>& done, double seconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < deadline) {
    if (done()) return true;
    ros::WallDuration(0.05).sleep();
  }
  return done();
}

class RendererVodTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/mmnvs_renderer_vod_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr) << std::strerror(errno);
    dir_ = pattern;
  }
  void TearDown() override {
    for (pid_t player : {player_, static_player_}) {
      if (player <= 0) continue;
      kill(-player, SIGINT);
      waitpid(player, nullptr, 0);
    }
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  std::string dir_;
  pid_t player_ = -1, static_player_ = -1;
};

}  // namespace

TEST_F(RendererVodTest, LiveFramesFollowTheCameraAndTheExportEqualsRenderConditioning) {
  const std::string vod = mm::test::dataDir() + "/vod";
  MMNVS_REQUIRE_DATA(mm::io::VodFrame({vod, kFirstFrame + kPoses - 1}).image());
  const std::string tools = MMNVS_TOOL_DIR;
  const std::string bag = dir_ + "/vod.bag";
  ASSERT_TRUE(rostest_helpers::run(tools + "/vod_to_bag --vod-root " + vod +
                                   " --frames 8350-8365 --output " + bag + " --quiet"));

  ros::NodeHandle nh, pnh("~");
  const std::string renderer = pnh.param<std::string>("renderer", "/conditioning_renderer");
  std::mutex mutex;
  std::vector<ros::Time> live;
  std::map<std::string, std::string> diagnostics;
  ros::Subscriber image = nh.subscribe<sensor_msgs::Image>(
      "conditioning/image", 32, [&](const sensor_msgs::ImageConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        live.push_back(msg->header.stamp);
        EXPECT_EQ(msg->height, 176u);
        EXPECT_EQ(msg->width, 320u);
      });
  ros::Subscriber diag =
      rostest_helpers::subscribeDiagnostics(nh, {"conditioning_renderer"}, mutex, diagnostics);
  // Printed when the export fails: which input the pipeline lost shows in both nodelets' counts.
  std::map<std::string, std::string> depth_diagnostics;
  ros::Subscriber depth_diag =
      rostest_helpers::subscribeDiagnostics(nh, {"depth completion"}, mutex, depth_diagnostics);
  const auto counts = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    std::string text = "renderer diagnostics:";
    for (const auto& kv : diagnostics)
      text += " [" + kv.first + ": " + kv.second + "]";
    text += "\ndepth completion diagnostics:";
    for (const auto& kv : depth_diagnostics)
      text += " [" + kv.first + ": " + kv.second + "]";
    return text;
  };

  // Simulated time: until the bag's clock runs, a slow clock below its first stamp (1 s) lets the
  // action client start (it waits for a valid time) and the server's status timer fire.
  ros::Publisher clock = nh.advertise<rosgraph_msgs::Clock>("/clock", 1);
  std::atomic<bool> bag_clock{false};
  std::thread early_clock([&] {
    rosgraph_msgs::Clock now;
    for (int tick = 1; !bag_clock && tick < 900 && ros::ok(); ++tick) {
      now.clock = ros::Time(0.001 * tick);
      clock.publish(now);
      ros::WallDuration(0.05).sleep();
    }
  });
  struct JoinOnExit {
    std::atomic<bool>& stop;
    std::thread& thread;
    ~JoinOnExit() {
      stop = true;
      thread.join();
    }
  } join_on_exit{bag_clock, early_clock};
  Client client(nh, renderer + "/export_trajectory");
  ASSERT_TRUE(
      waitWall([&] { return client.isServerConnected() && image.getNumPublishers() > 0; }, 60.0))
      << "the renderer's action server or conditioning/image never appeared";
  multimodal_nvs::ExportTrajectoryGoal goal;
  goal.num_poses = kPoses;
  goal.num_frames = 121;
  goal.output_dir = dir_ + "/export";
  goal.timeout = 120.0;  // the export takes ~10 s; a lost input fails in 2 minutes, not 5
  client.sendGoal(goal);

  // The export asked for a keyframe and keeps the inputs subscribed: play the bag. Its one radar
  // scan comes with the first image, so the radar -> camera extrinsic (/tf_static, latched) is
  // played first by a player of its own: within one player the two race, and the depth nodelet's
  // tf_timeout counts from before the bag's clock starts. Both players stay alive (-k) so that
  // the last images, 7 MB each, are delivered before their publisher goes away.
  // --wait-for-subscribers is satisfied by one subscriber per topic, but the camera topic has two
  // (the depth nodelet, the renderer) and its first image is the keyframe's: --delay gives the
  // second one time to connect on a loaded machine.
  ASSERT_TRUE(waitWall([&] { return client.getState() == State::ACTIVE; }, 10.0));
  static_player_ =
      rostest_helpers::spawn({"rosbag", "play", "--quiet", "-k", bag, "--topics", "/tf_static"});
  ASSERT_GT(static_player_, 0);
  ros::WallDuration(2.0).sleep();
  bag_clock = true;
  early_clock.join();
  early_clock = std::thread([] {});
  player_ = rostest_helpers::spawn({"rosbag", "play", "--clock", "--quiet", "-k", "--delay=2.0",
                                    bag, "--wait-for-subscribers", "--topics", "/camera/image_raw",
                                    "/camera/camera_info", "/radar/points", "/tf"});
  ASSERT_GT(player_, 0);
  ASSERT_TRUE(waitWall([&] { return client.getState().isDone(); }, 150.0)) << "export never ended\n"
                                                                           << counts();
  int status = 0;
  EXPECT_EQ(waitpid(player_, &status, WNOHANG), 0) << "rosbag play ended early";
  ASSERT_EQ(client.getState(), State::SUCCEEDED) << client.getState().getText() << "\n" << counts();
  const auto result = client.getResult();
  EXPECT_EQ(result->poses, kPoses);
  EXPECT_EQ(result->frames, 121);
  const std::string folder = result->folder;
  ASSERT_TRUE(fs::is_directory(folder)) << folder;
  EXPECT_FALSE(fs::exists(folder + ".partial"));

  // tf mode: one live frame per camera image, stamped as the bag's 10 Hz images from 1 s.
  ASSERT_TRUE(waitWall(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return live.size() >= std::size_t(kPoses);
      },
      30.0));
  {
    std::lock_guard<std::mutex> lock(mutex);
    std::vector<ros::Time> expected;
    for (int i = 0; i < kPoses; ++i)
      expected.push_back(ros::Time(1.0 + 0.1 * i));
    std::sort(live.begin(), live.end());
    EXPECT_EQ(live, expected);
  }

  // The recorded poses are VoD's odomToCamera (through tf's quaternions: not bit-exact).
  for (int j = 0; j < kPoses; ++j) {
    char name[32];
    std::snprintf(name, sizeof name, "/keyframe/poses/%03d.json", j);
    const Eigen::Matrix4d recorded = mm::io::readVodPose(folder + name, "odomToCamera");
    const Eigen::Matrix4d truth =
        mm::io::readVodPose(mm::io::VodFrame({vod, kFirstFrame + j}).pose(), "odomToCamera");
    EXPECT_LT((recorded - truth).cwiseAbs().maxCoeff(), 1e-6) << "pose " << j;
  }
  EXPECT_EQ(count(readText(folder + "/metrics.json"), "\"frame\": "), std::size_t(kPoses));

  // render_conditioning on the export's keyframe and poses writes the same arrays.
  std::string command;
  {
    std::istringstream lines(readText(folder + "/keyframe/render_conditioning.txt"));
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("render_conditioning ", 0) == 0) command = line;
  }
  ASSERT_FALSE(command.empty());
  const std::string tool_output = dir_ + "/render_conditioning";
  command.replace(command.find("OUTPUT"), 6, tool_output);
  ASSERT_TRUE(rostest_helpers::run("cd " + folder + " && " + tools + "/" + command + " > " + dir_ +
                                   "/render_conditioning.json"))
      << command;
  for (const char* array : {"rendered_warp_images.npy", "rendered_warp_masks.npy"}) {
    const std::string ours = readText(folder + "/gen3c/" + array);
    EXPECT_GT(ours.size(), 121u * 176u * 320u * 4u);
    EXPECT_TRUE(ours == readText(tool_output + "/gen3c/" + array)) << array << " differs";
  }

  // A goal cancelled while it waits for a keyframe (the bag is over): preempted, no folder left.
  client.sendGoal(goal);
  ASSERT_TRUE(waitWall([&] { return client.getState() == State::ACTIVE; }, 10.0));
  client.cancelGoal();
  ASSERT_TRUE(waitWall([&] { return client.getState().isDone(); }, 10.0));
  EXPECT_EQ(client.getState(), State::PREEMPTED);
  std::size_t folders = 0;
  for (const auto& entry : fs::directory_iterator(dir_ + "/export")) {
    EXPECT_EQ(entry.path().string(), folder);
    ++folders;
  }
  EXPECT_EQ(folders, 1u);
  EXPECT_TRUE(rostest_helpers::waitFor(
      mutex, [&] { return diagnostics["exports cancelled"] == "1"; }, 10.0))
      << "the cancel was not counted";
  EXPECT_EQ(diagnostics["exports complete"], "1");
}

int main(int argc, char** argv) {
  return rostest_helpers::runWithSpinner(argc, argv, "test_renderer_vod", 2);
}
