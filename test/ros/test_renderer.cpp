// gtest-in-rostest for the ConditioningRenderer nodelet (or node), two instances started by
// renderer.test: /live (trajectory_source tf) and /burst (trajectory_source preset). The test plays
// the camera and the depth nodelet: it publishes image + depth/image + depth/mask +
// depth/camera_info with equal stamps and the camera pose on /tf, and checks what comes out.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "multimodal_nvs/core/io/npy.hpp"
#include "rostest_helpers.hpp"

namespace enc = sensor_msgs::image_encodings;
namespace io = multimodal_nvs::io;

namespace {

constexpr int kH = 120, kW = 160;
constexpr double kF = 80.0, kCx = 80.0, kCy = 60.0;
constexpr float kPlaneDepth = 4.0f;  // a fronto-parallel plane: 0.1 m sideways = 2 pixels
constexpr const char* kCameraFrame = "renderer_test_camera";
constexpr const char* kWorldFrame = "odom";

/// Pixels of the image without depth (NaN in depth/image, 0 in depth/mask).
bool inputHole(int v, int u) {
  return v >= 40 && v < 60 && u >= 100 && u < 120;
}

cv::Vec3b colourAt(int v, int u) {
  static const cv::Mat colours = [] {
    cv::Mat m(kH, kW, CV_8UC3);
    cv::RNG rng(3);
    rng.fill(m, cv::RNG::UNIFORM, 0, 256);
    return m;
  }();
  return colours.at<cv::Vec3b>(v, u);
}

struct InputSet {
  sensor_msgs::Image image, depth, mask;
  sensor_msgs::CameraInfo info;
};

/// A good set: rgb8 image, depth and mask on a stride-`s` grid of it (the depth nodelet's
/// `stride`), CameraInfo of that grid (K / s).
InputSet goodSet(const ros::Time& stamp, int s) {
  InputSet set;
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = kCameraFrame;
  set.image.header = header;
  set.image.height = kH;
  set.image.width = kW;
  set.image.encoding = enc::RGB8;
  set.image.step = kW * 3;
  set.image.data.resize(kH * kW * 3);
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const cv::Vec3b c = colourAt(v, u);
      std::memcpy(&set.image.data[(v * kW + u) * 3], c.val, 3);
    }
  }
  const int gh = (kH + s - 1) / s, gw = (kW + s - 1) / s;
  set.depth.header = set.mask.header = set.info.header = header;
  set.depth.height = set.mask.height = set.info.height = gh;
  set.depth.width = set.mask.width = set.info.width = gw;
  set.depth.encoding = enc::TYPE_32FC1;
  set.depth.step = gw * 4;
  set.depth.data.resize(gh * gw * 4);
  set.mask.encoding = enc::MONO8;
  set.mask.step = gw;
  set.mask.data.resize(gh * gw);
  for (int r = 0; r < gh; ++r) {
    for (int c = 0; c < gw; ++c) {
      const bool hole = inputHole(r * s, c * s);
      const float z = hole ? std::numeric_limits<float>::quiet_NaN() : kPlaneDepth;
      std::memcpy(&set.depth.data[(r * gw + c) * 4], &z, 4);
      set.mask.data[r * gw + c] = hole ? 0 : 255;
    }
  }
  set.info.distortion_model = "plumb_bob";
  set.info.D.assign(5, 0.0);
  set.info.K = {kF / s, 0, kCx / s, 0, kF / s, kCy / s, 0, 0, 1};
  set.info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  set.info.P = {kF / s, 0, kCx / s, 0, 0, kF / s, kCy / s, 0, 0, 0, 1, 0};
  return set;
}

/// Everything one renderer instance publishes, by stamp.
struct Outputs {
  std::map<ros::Time, sensor_msgs::ImageConstPtr> image, mask, depth, preview;
  std::map<ros::Time, sensor_msgs::CameraInfoConstPtr> info;
  void clear() { *this = Outputs(); }
};

class RendererTest : public ::testing::Test {
 protected:
  /// Subscribes to /NS/conditioning/* and advertises /NS/image, /NS/depth/*.
  void connect(const std::string& ns) {
    ns_ = ns;
    auto image_cb = [this](std::map<ros::Time, sensor_msgs::ImageConstPtr>* into) {
      return [this, into](const sensor_msgs::ImageConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex_);
        (*into)[msg->header.stamp] = msg;
      };
    };
    subs_.push_back(
        nh_.subscribe<sensor_msgs::Image>(ns + "/conditioning/image", 50, image_cb(&out_.image)));
    subs_.push_back(
        nh_.subscribe<sensor_msgs::Image>(ns + "/conditioning/mask", 50, image_cb(&out_.mask)));
    subs_.push_back(
        nh_.subscribe<sensor_msgs::Image>(ns + "/conditioning/depth", 50, image_cb(&out_.depth)));
    subs_.push_back(nh_.subscribe<sensor_msgs::Image>(ns + "/conditioning/preview", 50,
                                                      image_cb(&out_.preview)));
    subs_.push_back(nh_.subscribe<sensor_msgs::CameraInfo>(
        ns + "/conditioning/camera_info", 50, [this](const sensor_msgs::CameraInfoConstPtr& msg) {
          std::lock_guard<std::mutex> lock(mutex_);
          out_.info[msg->header.stamp] = msg;
        }));
    // diagnostic_updater names the status "<node name without the leading />: <task>".
    subs_.push_back(rostest_helpers::subscribeDiagnostics(
        nh_, {ns.substr(1) + "/", "conditioning renderer"}, mutex_, diagnostics_));
    image_pub_ = nh_.advertise<sensor_msgs::Image>(ns + "/image", 5);
    depth_pub_ = nh_.advertise<sensor_msgs::Image>(ns + "/depth/image", 5);
    mask_pub_ = nh_.advertise<sensor_msgs::Image>(ns + "/depth/mask", 5);
    info_pub_ = nh_.advertise<sensor_msgs::CameraInfo>(ns + "/depth/camera_info", 5);
  }

  /// The camera `x` metres along the world's x axis (camera axes = world axes) at `stamp`.
  void sendPose(const ros::Time& stamp, double x) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = kWorldFrame;
    t.child_frame_id = kCameraFrame;
    t.transform.translation.x = x;
    t.transform.rotation.w = 1.0;
    tf_.sendTransform(t);
  }

  void publish(const InputSet& set) {
    image_pub_.publish(set.image);
    depth_pub_.publish(set.depth);
    mask_pub_.publish(set.mask);
    info_pub_.publish(set.info);
  }

  bool waitFor(const std::function<bool()>& done, double seconds) {
    return rostest_helpers::waitFor(mutex_, done, seconds);
  }

  /// Repeats good sets (pose `x`) until the lazily subscribing node answers one.
  bool warmUp(double x) {
    for (int attempt = 0; attempt < 60; ++attempt) {
      const ros::Time stamp = ros::Time::now();
      sendPose(stamp, x);
      ros::WallDuration(0.05).sleep();
      publish(goodSet(stamp, 1));
      if (waitFor([&] { return out_.image.count(stamp) > 0; }, 1.0)) return true;
    }
    return false;
  }

  /// All five outputs of `stamp` arrived.
  bool complete(const ros::Time& stamp) const {
    return out_.image.count(stamp) && out_.mask.count(stamp) && out_.depth.count(stamp) &&
           out_.preview.count(stamp) && out_.info.count(stamp);
  }

  bool trigger(const std::string& service, std::string& message) {
    const std::string name = ns_ + "/conditioning_renderer/" + service;
    if (!ros::service::waitForService(name, ros::Duration(20.0))) {
      message = name + " not available";
      return false;
    }
    std_srvs::Trigger srv;
    if (!ros::service::call(name, srv)) {
      message = name + " call failed";
      return false;
    }
    message = srv.response.message;
    return srv.response.success;
  }

  ros::NodeHandle nh_;
  std::string ns_;
  ros::Publisher image_pub_, depth_pub_, mask_pub_, info_pub_;
  tf2_ros::TransformBroadcaster tf_;
  std::mutex mutex_;
  Outputs out_;
  std::map<std::string, std::string> diagnostics_;
  // Last, so destroyed first: a callback still arriving must not write into the members above
  // after they are gone (the spinner threads run until after the tests).
  std::vector<ros::Subscriber> subs_;
};

/// Checks header, sizes and encodings of the five outputs of one frame; mask values exactly
/// {0,255}, depth NaN exactly in holes.
void expectWellFormed(const Outputs& out, const ros::Time& stamp, int h, int w) {
  const auto& image = out.image.at(stamp);
  const auto& mask = out.mask.at(stamp);
  const auto& depth = out.depth.at(stamp);
  const auto& preview = out.preview.at(stamp);
  const auto& info = out.info.at(stamp);
  for (const auto* msg : {&image, &mask, &depth, &preview}) {
    EXPECT_EQ((*msg)->header.frame_id, kCameraFrame);
    EXPECT_EQ(int((*msg)->height), h);
    EXPECT_EQ(int((*msg)->width), w);
  }
  EXPECT_EQ(info->header.frame_id, kCameraFrame);
  EXPECT_EQ(int(info->height), h);
  EXPECT_EQ(int(info->width), w);
  EXPECT_EQ(image->encoding, enc::RGB8);
  EXPECT_EQ(preview->encoding, enc::RGB8);
  EXPECT_EQ(mask->encoding, enc::MONO8);
  EXPECT_EQ(depth->encoding, enc::TYPE_32FC1);
  int holes = 0;
  for (int i = 0; i < h * w; ++i) {
    const std::uint8_t m = mask->data[i * mask->step / w];
    ASSERT_TRUE(m == 0 || m == 255) << "mask value " << int(m);
    float z;
    std::memcpy(&z, &depth->data[(i / w) * depth->step + 4 * (i % w)], 4);
    if (m == 0) {
      ASSERT_TRUE(std::isnan(z)) << "depth " << z << " in a hole";
      ++holes;
    } else {
      ASSERT_TRUE(std::isfinite(z) && z > 0.0f) << z;
    }
  }
  EXPECT_LT(holes, h * w / 2) << "mostly holes";
}

cv::Vec3b rgbAt(const sensor_msgs::Image& image, int v, int u) {
  const std::uint8_t* p = &image.data[v * image.step + 3 * u];
  return cv::Vec3b(p[0], p[1], p[2]);
}

/// Every covered pixel (v, u) has the keyframe colour of (v, u + shift) (a pure sideways motion in
/// front of the plane); returns the number of covered pixels compared.
int expectShiftedColours(const Outputs& out, const ros::Time& stamp, int shift) {
  const auto& image = *out.image.at(stamp);
  const auto& mask = *out.mask.at(stamp);
  const auto& depth = *out.depth.at(stamp);
  int compared = 0, wrong = 0;
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const int src = u + shift;
      if (mask.data[v * mask.step + u] == 0) {
        if (src >= 0 && src < kW && !inputHole(v, src)) continue;  // edge-filtered: allowed
        continue;
      }
      EXPECT_TRUE(src >= 0 && src < kW && !inputHole(v, src))
          << "covered pixel " << u << "," << v << " has no source";
      if (src < 0 || src >= kW) continue;
      float z;
      std::memcpy(&z, &depth.data[v * depth.step + 4 * u], 4);
      EXPECT_NEAR(z, kPlaneDepth, 1e-3f);
      // The input image's rgb8 bytes are the colour table's three bytes in order.
      if (rgbAt(image, v, u) != colourAt(v, src)) ++wrong;
      ++compared;
    }
  }
  EXPECT_EQ(wrong, 0) << "of " << compared << " covered pixels (shift " << shift << ")";
  return compared;
}

}  // namespace

TEST_F(RendererTest, TfModeRendersTheKeyframeIntoTheLiveCameraPose) {
  connect("/live");
  // Warm up: the node subscribes lazily; the first set it receives becomes the keyframe (pose 0).
  ASSERT_TRUE(warmUp(0.0)) << "the renderer never answered";
  ros::WallDuration(0.5).sleep();

  // Same pose as the keyframe: the keyframe's colours at every covered pixel.
  const ros::Time same = ros::Time::now();
  sendPose(same, 0.0);
  ros::WallDuration(0.05).sleep();
  publish(goodSet(same, 1));
  ASSERT_TRUE(waitFor([&] { return complete(same); }, 10.0)) << "no output at the target stamp";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    expectWellFormed(out_, same, kH, kW);
    EXPECT_GT(expectShiftedColours(out_, same, 0), kH * kW * 8 / 10);
    for (int v = 40; v < 60; ++v) {
      for (int u = 100; u < 120; ++u) {
        ASSERT_EQ(out_.mask.at(same)->data[v * kW + u], 0) << "input hole rendered at " << u;
      }
    }
    const auto& info = *out_.info.at(same);
    EXPECT_DOUBLE_EQ(info.K[0], kF);
    EXPECT_DOUBLE_EQ(info.K[2], kCx);
    EXPECT_DOUBLE_EQ(info.K[4], kF);
    EXPECT_DOUBLE_EQ(info.K[5], kCy);
  }

  // The camera 0.1 m to the right: the plane at 4 m moves 2 pixels to the left.
  const ros::Time moved = ros::Time::now();
  sendPose(moved, 0.1);
  ros::WallDuration(0.05).sleep();
  publish(goodSet(moved, 1));
  ASSERT_TRUE(waitFor([&] { return complete(moved); }, 10.0));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    expectWellFormed(out_, moved, kH, kW);
    EXPECT_GT(expectShiftedColours(out_, moved, 2), kH * kW * 8 / 10);
    for (int v = 0; v < kH; ++v) {
      EXPECT_EQ(out_.mask.at(moved)->data[v * kW + kW - 1], 0) << "uncovered right edge";
    }
  }

  // The image before its pose (a player's /tf on another connection, a slow tf publisher): held
  // until tf reaches its stamp (tf_timeout 0.5 s from its arrival), then rendered like the others.
  const ros::Time late_pose = ros::Time::now();
  publish(goodSet(late_pose, 1));
  ros::WallDuration(0.25).sleep();
  sendPose(late_pose, 0.1);
  ASSERT_TRUE(waitFor([&] { return complete(late_pose); }, 10.0))
      << "an image whose pose came 0.25 s after it was not rendered";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_GT(expectShiftedColours(out_, late_pose, 2), kH * kW * 8 / 10);
  }

  // ~set_keyframe: the next set (at 0.1 m) is the new reference; a set back at 0 m then shows the
  // plane 2 pixels to the right.
  std::string message;
  ASSERT_TRUE(trigger("set_keyframe", message)) << message;
  const ros::Time key = ros::Time::now();
  sendPose(key, 0.1);
  ros::WallDuration(0.05).sleep();
  publish(goodSet(key, 1));
  ASSERT_TRUE(waitFor([&] { return complete(key); }, 10.0));
  const ros::Time back = ros::Time::now();
  sendPose(back, 0.0);
  ros::WallDuration(0.05).sleep();
  publish(goodSet(back, 1));
  ASSERT_TRUE(waitFor([&] { return complete(back); }, 10.0));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_GT(expectShiftedColours(out_, key, 0), kH * kW * 8 / 10);
    EXPECT_GT(expectShiftedColours(out_, back, -2), kH * kW * 8 / 10);
  }
}

TEST_F(RendererTest, TfModeDropsEachBadInputAndRecovers) {
  connect("/live");
  ASSERT_TRUE(warmUp(0.0)) << "the renderer never answered";
  ros::WallDuration(0.5).sleep();
  // A bad depth set is dropped, but its camera image still gets the keyframe rendered into its
  // pose (the live view follows the camera, not the depth sets); a bad image or a missing pose
  // gets no output.
  const struct {
    const char* name;
    const char* reason;
    std::function<void(InputSet&)> breakIt;
    bool camera_image_rendered;
  } cases[] = {
      {"mask smaller than depth", "mask_size",
       [](InputSet& s) {
         s.mask.width = kW / 2;
         s.mask.step = kW / 2;
       },
       true},
      {"depth grid that is no stride grid of the image", "grid_size",
       [](InputSet& s) {
         s = goodSet(s.image.header.stamp, 1);
         for (auto* img : {&s.depth, &s.mask})
           img->width = 70;
         s.depth.step = 70 * 4;
         s.mask.step = 70;
         s.info.width = 70;
       },
       true},
      {"CameraInfo with K all zero", "camera_info_intrinsics",
       [](InputSet& s) { s.info.K.fill(0.0); }, true},
      {"depth as 16SC1", "depth_image", [](InputSet& s) { s.depth.encoding = enc::TYPE_16SC1; },
       true},
      {"image as yuv422", "image_encoding", [](InputSet& s) { s.image.encoding = enc::YUV422; },
       false},
      {"camera frame without a pose", "transform_unavailable",
       [](InputSet& s) {
         for (auto* img : {&s.image, &s.depth, &s.mask})
           img->header.frame_id = "nobody";
         s.info.header.frame_id = "nobody";
       },
       false},
  };
  std::vector<ros::Time> bad_stamps;
  for (const auto& bad : cases) {
    const ros::Time stamp = ros::Time::now();
    sendPose(stamp, 0.0);
    InputSet set = goodSet(stamp, 1);
    bad.breakIt(set);
    publish(set);
    bad_stamps.push_back(stamp);
    ros::WallDuration(0.7).sleep();  // > tf_timeout, so sets never overlap in the synchronizer
  }
  const ros::Time good = ros::Time::now();
  sendPose(good, 0.0);
  ros::WallDuration(0.05).sleep();
  publish(goodSet(good, 1));
  EXPECT_TRUE(waitFor([&] { return complete(good); }, 10.0)) << "no output after the bad sets";

  auto counted = [this](const char* reason) {
    auto it = diagnostics_.find(std::string("rejected ") + reason);
    return it != diagnostics_.end() && it->second != "0";
  };
  waitFor(
      [&] {
        for (const auto& bad : cases)
          if (!counted(bad.reason)) return false;
        return true;
      },
      10.0);
  std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t i = 0; i < bad_stamps.size(); ++i) {
    EXPECT_EQ(out_.image.count(bad_stamps[i]), cases[i].camera_image_rendered ? 1u : 0u)
        << "output for bad input: " << cases[i].name;
    EXPECT_TRUE(counted(cases[i].reason)) << cases[i].name << " not counted as " << cases[i].reason;
  }
}

TEST_F(RendererTest, PresetModeRendersBurstsAndExportsGen3cFolders) {
  connect("/burst");
  constexpr int kFrames = 5, kRh = 48, kRw = 64;  // test/ros/renderer_burst_params.yaml
  constexpr double kFps = 10.0;
  // Export on: set through dynamic_reconfigure, as a user would.
  const std::string export_dir =
      ::testing::TempDir() + "renderer_export_" + std::to_string(getpid());
  {
    const std::string name = "/burst/conditioning_renderer/set_parameters";
    ASSERT_TRUE(ros::service::waitForService(name, ros::Duration(20.0)));
    dynamic_reconfigure::Reconfigure srv;
    dynamic_reconfigure::StrParameter p;
    p.name = "export_dir";
    p.value = export_dir;
    srv.request.config.strs.push_back(p);
    ASSERT_TRUE(ros::service::call(name, srv));
    bool applied = false;
    for (const auto& s : srv.response.config.strs)
      applied |= s.name == "export_dir" && s.value == export_dir;
    ASSERT_TRUE(applied) << "export_dir not applied";
  }

  // Warm up until the node holds a keyframe (its first set, depth on a stride-2 grid).
  std::string message;
  bool rendered = false;
  for (int attempt = 0; attempt < 60 && !rendered; ++attempt) {
    publish(goodSet(ros::Time::now(), 2));
    ros::WallDuration(0.3).sleep();
    rendered = trigger("render", message);
  }
  ASSERT_TRUE(rendered) << message;
  ros::WallDuration(1.0).sleep();  // let the warm-up bursts drain

  // ~render: exactly one burst of kFrames frames, stamped keyframe + i / fps.
  {
    std::lock_guard<std::mutex> lock(mutex_);
    out_.clear();
  }
  ASSERT_TRUE(trigger("render", message)) << message;
  EXPECT_TRUE(waitFor(
      [&] { return out_.image.size() >= kFrames && out_.preview.size() >= kFrames; }, 10.0));
  ros::WallDuration(0.5).sleep();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_EQ(out_.image.size(), std::size_t(kFrames));
    const ros::Time first = out_.image.begin()->first;
    int i = 0;
    for (const auto& kv : out_.image) {
      EXPECT_NEAR((kv.first - first).toSec(), i / kFps, 1e-6) << "frame " << i;
      ASSERT_TRUE(complete(kv.first)) << "frame " << i;
      expectWellFormed(out_, kv.first, kRh, kRw);
      // Intrinsics scaled per axis from 160x120 to 64x48.
      const auto& info = *out_.info.at(kv.first);
      EXPECT_DOUBLE_EQ(info.K[0], kF * kRw / kW);
      EXPECT_DOUBLE_EQ(info.K[4], kF * kRh / kH);
      ++i;
    }
  }
  const std::string marker = "GEN3C folder ";
  ASSERT_NE(message.find(marker), std::string::npos) << message;
  const std::string folder = message.substr(message.find(marker) + marker.size());
  EXPECT_EQ(folder.rfind(export_dir, 0), 0u) << folder;
  const io::NpyArray images = io::readNpy(folder + "/rendered_warp_images.npy");
  const io::NpyArray masks = io::readNpy(folder + "/rendered_warp_masks.npy");
  EXPECT_EQ(images.dtype, "<f4");
  ASSERT_EQ(images.shape, (std::vector<std::size_t>{1, kFrames, 1, 3, kRh, kRw}));
  ASSERT_EQ(masks.shape, (std::vector<std::size_t>{1, kFrames, 1, 1, kRh, kRw}));
  const std::vector<float> rgb = images.asFloat(), m = masks.asFloat();
  const std::size_t plane = kRh * kRw;
  for (std::size_t f = 0; f < kFrames; ++f) {
    for (std::size_t p = 0; p < plane; ++p) {
      const float mv = m[f * plane + p];
      ASSERT_TRUE(mv == 0.0f || mv == 1.0f) << mv;
      for (std::size_t c = 0; c < 3 && mv == 0.0f; ++c)
        ASSERT_EQ(rgb[(f * 3 + c) * plane + p], -1.0f);
    }
  }
  EXPECT_EQ(cv::imread(folder + "/input_image.png").size(), cv::Size(kRw, kRh));

  // ~set_keyframe: the next set is a keyframe, which renders (and exports) a burst by itself.
  {
    std::lock_guard<std::mutex> lock(mutex_);
    out_.clear();
  }
  ASSERT_TRUE(trigger("set_keyframe", message)) << message;
  const ros::Time key = ros::Time::now();
  publish(goodSet(key, 2));
  EXPECT_TRUE(waitFor([&] { return out_.image.size() >= kFrames; }, 10.0));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_EQ(out_.image.size(), std::size_t(kFrames));
    EXPECT_EQ(out_.image.begin()->first, key);
    EXPECT_NEAR((out_.image.rbegin()->first - key).toSec(), (kFrames - 1) / kFps, 1e-6);
  }
  char name[32];
  std::snprintf(name, sizeof name, "/%010u_%09u", key.sec, key.nsec);
  const std::string key_masks = export_dir + name + "/rendered_warp_masks.npy";
  // The folder appears (renamed from .partial) once the burst is written, after its last frame.
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(10.0);
  while (!std::ifstream(key_masks).good() && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.05).sleep();
  }
  EXPECT_EQ(io::readNpy(key_masks).shape, (std::vector<std::size_t>{1, kFrames, 1, 1, kRh, kRw}));
}

int main(int argc, char** argv) {
  return rostest_helpers::runWithSpinner(argc, argv, "test_renderer", 2);
}
