// gtest-in-rostest: the synthetic scene through the running depth completion node. Depth at probe
// pixels vs analytic depth, NaN exactly where masked, variance growing away from the points,
// cloud colours equal to image colours, and every output carrying the image's header.
#include <gtest/gtest.h>
#include <multimodal_nvs/DepthCompletionStats.h>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <mutex>

#include "multimodal_nvs/core/common/colormap.hpp"
#include "rostest_helpers.hpp"
#include "synthetic_scene.hpp"

namespace ss = synthetic_scene;

namespace {

/// The latest message of every output topic.
struct Outputs {
  std::mutex mutex;
  sensor_msgs::ImageConstPtr depth, variance, mask, depth_color, stddev_color;
  sensor_msgs::CameraInfoConstPtr info;
  sensor_msgs::PointCloud2ConstPtr points;
  multimodal_nvs::DepthCompletionStatsConstPtr stats;

  bool completeFor(const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(mutex);
    return depth && variance && mask && depth_color && stddev_color && info && points && stats &&
           depth->header.stamp == stamp && variance->header.stamp == stamp &&
           mask->header.stamp == stamp && depth_color->header.stamp == stamp &&
           stddev_color->header.stamp == stamp && info->header.stamp == stamp &&
           points->header.stamp == stamp && stats->header.stamp == stamp;
  }
};

template <class Msg>
ros::Subscriber keepLatest(ros::NodeHandle& nh, const std::string& topic, Outputs& outputs,
                           boost::shared_ptr<const Msg> Outputs::*slot) {
  return nh.subscribe<Msg>(topic, 5, [&outputs, slot](const boost::shared_ptr<const Msg>& msg) {
    std::lock_guard<std::mutex> lock(outputs.mutex);
    outputs.*slot = msg;
  });
}

float floatAt(const sensor_msgs::Image& image, int u, int v) {
  float value;
  std::memcpy(&value, &image.data[std::size_t(v) * image.step + 4 * u], sizeof value);
  return value;
}

class DepthSceneTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ros::NodeHandle nh;
    outputs_ = new Outputs;
    Outputs& out = *outputs_;
    subscribers_ = new std::vector<ros::Subscriber>{
        keepLatest(nh, "depth/image", out, &Outputs::depth),
        keepLatest(nh, "depth/camera_info", out, &Outputs::info),
        keepLatest(nh, "depth/variance", out, &Outputs::variance),
        keepLatest(nh, "depth/mask", out, &Outputs::mask),
        keepLatest(nh, "depth/image_color", out, &Outputs::depth_color),
        keepLatest(nh, "depth/stddev_color", out, &Outputs::stddev_color),
        keepLatest(nh, "depth/points", out, &Outputs::points),
        keepLatest(nh, "depth/stats", out, &Outputs::stats)};
    static tf2_ros::StaticTransformBroadcaster static_tf;
    static_tf.sendTransform(ss::sensorToCameraMsg(ros::Time(0)));
    const ss::InputPublishers inputs(nh, 1);
    // For the compressed_input variant: the same image as PNG (lossless, so colours stay exact).
    ros::Publisher compressed_pub =
        nh.advertise<sensor_msgs::CompressedImage>("image/compressed", 1);
    sensor_msgs::CompressedImage png;
    png.format = "bgr8; png compressed bgr8";
    {
      sensor_msgs::Image bgr = ss::image(ros::Time(0));
      const cv::Mat view(bgr.height, bgr.width, CV_8UC3, bgr.data.data(), bgr.step);
      cv::imencode(".png", view, png.data);
    }
    // The node subscribes lazily, once it sees our output subscriptions: repeat until it answers.
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(40.0);
    while (ros::ok() && ros::WallTime::now() < deadline) {
      stamp_ = ros::Time::now();
      inputs.publish(ss::inputSet(stamp_));
      png.header = ss::header(stamp_, ss::kCameraFrame);
      compressed_pub.publish(png);
      for (int i = 0; i < 20 && !out.completeFor(stamp_); ++i)
        ros::WallDuration(0.05).sleep();
      if (out.completeFor(stamp_)) return;
    }
  }

  void SetUp() override { ASSERT_TRUE(outputs_->completeFor(stamp_)) << "no complete output set"; }

  static Outputs* outputs_;
  static std::vector<ros::Subscriber>* subscribers_;
  static ros::Time stamp_;
};

Outputs* DepthSceneTest::outputs_ = nullptr;
std::vector<ros::Subscriber>* DepthSceneTest::subscribers_ = nullptr;
ros::Time DepthSceneTest::stamp_;

TEST_F(DepthSceneTest, HeadersArePropagated) {
  for (const std_msgs::Header* h :
       {&outputs_->depth->header, &outputs_->variance->header, &outputs_->mask->header,
        &outputs_->info->header, &outputs_->points->header, &outputs_->stats->header}) {
    EXPECT_EQ(h->stamp, stamp_);
    EXPECT_EQ(h->frame_id, ss::kCameraFrame);
  }
  EXPECT_EQ(outputs_->depth->encoding, sensor_msgs::image_encodings::TYPE_32FC1);
  EXPECT_EQ(outputs_->variance->encoding, sensor_msgs::image_encodings::TYPE_32FC1);
  EXPECT_EQ(outputs_->mask->encoding, sensor_msgs::image_encodings::MONO8);
  EXPECT_EQ(int(outputs_->depth->width), ss::kWidth);
  EXPECT_EQ(int(outputs_->depth->height), ss::kHeight);
  EXPECT_EQ(outputs_->info->K[0], ss::kFx);  // stride 1: the input camera unchanged
  EXPECT_EQ(outputs_->info->K[2], ss::kCx);
}

TEST_F(DepthSceneTest, DepthMatchesTheSceneAtProbes) {
  const sensor_msgs::Image& depth = *outputs_->depth;
  // Probes at least 8 degrees from any depth edge and inside the region with returns.
  const int probes[][2] = {{160, 135}, {140, 150}, {40, 200}, {290, 110}, {20, 230}};
  for (const auto& p : probes) {
    const double expected = ss::analyticDepth(p[0], p[1]);
    EXPECT_NEAR(floatAt(depth, p[0], p[1]), expected, 0.15) << "pixel " << p[0] << "," << p[1];
  }
}

TEST_F(DepthSceneTest, NanExactlyWhereMasked) {
  const sensor_msgs::Image& depth = *outputs_->depth;
  const sensor_msgs::Image& mask = *outputs_->mask;
  int kept = 0;
  for (int v = 0; v < ss::kHeight; ++v) {
    for (int u = 0; u < ss::kWidth; ++u) {
      const std::uint8_t m = mask.data[std::size_t(v) * mask.step + u];
      ASSERT_TRUE(m == 0 || m == 255);
      ASSERT_EQ(m == 255, std::isfinite(floatAt(depth, u, v))) << "pixel " << u << "," << v;
      kept += m == 255;
    }
  }
  EXPECT_EQ(kept, int(outputs_->stats->kept_pixels));
  EXPECT_EQ(kept, int(std::lround(0.6 * ss::kWidth * ss::kHeight)));  // retain_percent 60
  // The sky has no return within the radius: never kept.
  EXPECT_TRUE(std::isnan(floatAt(depth, 160, 30)));
  EXPECT_TRUE(std::isnan(floatAt(depth, 10, 5)));
}

TEST_F(DepthSceneTest, VarianceGrowsAwayFromPoints) {
  const sensor_msgs::Image& variance = *outputs_->variance;
  const float on_points = floatAt(variance, 160, 136);  // a scene point sits at (160, 136)
  const float near_sky = floatAt(variance, 160, 90);    // 6 px (1.7 deg) above the last row
  const float sky = floatAt(variance, 160, 30);         // no point within the radius: the prior
  EXPECT_LT(on_points, near_sky);
  EXPECT_LT(near_sky, sky);
  EXPECT_NEAR(sky, 25.0 * 25.0, 1e-3);
  for (int v = 0; v < ss::kHeight; ++v) {
    for (int u = 0; u < ss::kWidth; ++u)
      ASSERT_GE(floatAt(variance, u, v), 0.0f);
  }
}

TEST_F(DepthSceneTest, CloudColoursDepthAndStddevMatchTheImages) {
  const sensor_msgs::PointCloud2& cloud = *outputs_->points;
  ASSERT_EQ(cloud.point_step, 20u);
  ASSERT_EQ(cloud.fields.size(), 5u);
  EXPECT_EQ(cloud.fields[3].name, "rgb");
  EXPECT_EQ(cloud.fields[4].name, "stddev");
  EXPECT_EQ(cloud.fields[4].offset, 16u);
  EXPECT_EQ(cloud.fields[4].datatype, sensor_msgs::PointField::FLOAT32);
  EXPECT_EQ(cloud.width, outputs_->stats->kept_pixels);  // cloud_stride 1
  for (std::size_t i = 0; i < cloud.width; ++i) {
    float xyz[3], stddev;
    std::uint32_t packed;
    std::memcpy(xyz, &cloud.data[i * 20], sizeof xyz);
    std::memcpy(&packed, &cloud.data[i * 20 + 12], sizeof packed);
    std::memcpy(&stddev, &cloud.data[i * 20 + 16], sizeof stddev);
    const int u = int(std::lround(ss::kFx * xyz[0] / xyz[2] + ss::kCx));
    const int v = int(std::lround(ss::kFy * xyz[1] / xyz[2] + ss::kCy));
    ASSERT_TRUE(u >= 0 && u < ss::kWidth && v >= 0 && v < ss::kHeight);
    std::uint8_t rgb[3];
    ss::colourAt(u, v, rgb);
    ASSERT_EQ(packed, (std::uint32_t(rgb[0]) << 16) | (std::uint32_t(rgb[1]) << 8) | rgb[2])
        << "point " << i << " at pixel " << u << "," << v;
    ASSERT_NEAR(xyz[2], floatAt(*outputs_->depth, u, v), 1e-4);
    ASSERT_NEAR(stddev, std::sqrt(floatAt(*outputs_->variance, u, v)), 1e-4);
  }
}

// The colour images: bgr8 on the depth grid, the fixed default ranges (depth 0..50 m turbo,
// standard deviation 0..10 m viridis), black where not kept / no prediction.
TEST_F(DepthSceneTest, ColourImagesMapDepthAndStddevOverFixedRanges) {
  const sensor_msgs::Image& depth = *outputs_->depth;
  const sensor_msgs::Image& variance = *outputs_->variance;
  const multimodal_nvs::ColorScale depth_scale(0.0, 50.0, cv::COLORMAP_TURBO);
  const multimodal_nvs::ColorScale stddev_scale(0.0, 10.0, cv::COLORMAP_VIRIDIS);
  for (const sensor_msgs::Image* image : {&*outputs_->depth_color, &*outputs_->stddev_color}) {
    ASSERT_EQ(image->encoding, sensor_msgs::image_encodings::BGR8);
    ASSERT_EQ(image->width, depth.width);
    ASSERT_EQ(image->height, depth.height);
    ASSERT_EQ(image->step, 3 * image->width);
  }
  int coloured = 0;
  for (int v = 0; v < ss::kHeight; ++v) {
    for (int u = 0; u < ss::kWidth; ++u) {
      const std::size_t at = std::size_t(v) * depth.width * 3 + 3 * u;
      const float z = floatAt(depth, u, v);
      const cv::Vec3b want_depth = std::isnan(z) ? depth_scale.noData() : depth_scale(z);
      const cv::Vec3b want_stddev = stddev_scale(std::sqrt(floatAt(variance, u, v)));
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_EQ(outputs_->depth_color->data[at + ch], want_depth[ch]) << u << "," << v;
        ASSERT_EQ(outputs_->stddev_color->data[at + ch], want_stddev[ch]) << u << "," << v;
      }
      coloured += !std::isnan(z);
    }
  }
  EXPECT_GT(coloured, 0);
}

TEST_F(DepthSceneTest, StatsDescribeTheInput) {
  const auto& stats = *outputs_->stats;
  EXPECT_EQ(stats.points_in, ss::sensorPoints().size());
  // All are sampled from image pixels; those on the left border column may round to u < 0.
  EXPECT_LE(stats.points_in_view, stats.points_in);
  EXPECT_GE(stats.points_in_view + 64, stats.points_in);
  EXPECT_GT(stats.neighbour_sets, 0u);
  EXPECT_GT(stats.compute_ms, 0.0f);
  EXPECT_GE(stats.latency_ms, stats.compute_ms);
}

}  // namespace

int main(int argc, char** argv) {
  return rostest_helpers::runWithSpinner(argc, argv, "test_depth_scene", 1);
}
