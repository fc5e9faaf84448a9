// completeDepthFrame and its steps on the synthetic scene: the sensor -> camera transform (at the
// cloud's stamp, or across the two stamps through a fixed frame), the point cap, the order in which
// faults are reported, the core's result unchanged; no master.
#include <gtest/gtest.h>
#include <tf2_ros/buffer.h>

#include <algorithm>
#include <cmath>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/hidden_returns.hpp"
#include "multimodal_nvs/ros/depth_frame.hpp"
#include "synthetic_scene.hpp"

namespace mm = multimodal_nvs;
namespace rc = multimodal_nvs::ros_conversions;
namespace scene = synthetic_scene;
using rc::InputFault;

namespace {

const rc::CloudToCamera kAtCloudStamp{ros::Duration(0.01), ""};

/// Largest entry of the difference: Eigen's isApprox on a 4x4 double matrix trips GCC 12's
/// -Wuninitialized inside its AVX-512 reduction.
double largestDifference(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  double largest = 0.0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c)
      largest = std::max(largest, std::abs(a.matrix()(r, c) - b.matrix()(r, c)));
  }
  return largest;
}

std_msgs::Header cameraHeader(const ros::Time& stamp) {
  std_msgs::Header header;
  header.frame_id = synthetic_scene::kCameraFrame;
  header.stamp = stamp;
  return header;
}

class DepthFrame : public testing::Test {
 protected:
  void SetUp() override {
    ros::Time::init();                  // tf2's lookup with a timeout reads the clock
    tf_.setUsingDedicatedThread(true);  // a listener's thread would fill it; here the test does
    tf_.setTransform(scene::sensorToCameraMsg(stamp_), "test", /*is_static=*/true);
    set_ = scene::inputSet(stamp_);
    ASSERT_TRUE(rc::frameImage(set_.image, image_).ok());
    settings_.params.model = mm::DepthModel::kKernel;  // fast; the pipeline is the same
    settings_.stride = 4;
  }

  rc::DepthFrameResult complete(int max_points = 0) {
    return rc::completeDepthFrame(set_.cloud, image_, set_.info, tf_, kAtCloudStamp, settings_,
                                  max_points, workspace_);
  }

  const ros::Time stamp_{100.0};
  tf2_ros::Buffer tf_;
  scene::InputSet set_;
  rc::FrameImage image_;
  mm::DepthCompletionSettings settings_;
  mm::DepthCompletionWorkspace workspace_;
};

TEST_F(DepthFrame, SensorToCameraIsTheTfTransformOrIdentityForTheCameraFrame) {
  Eigen::Isometry3d transform;
  const std_msgs::Header camera = cameraHeader(stamp_);
  ASSERT_TRUE(
      rc::lookupSensorToCamera(tf_, set_.cloud.header, camera, kAtCloudStamp, transform).ok());
  EXPECT_TRUE(transform.isApprox(scene::sensorToCamera(), 1e-9));

  std_msgs::Header in_camera = set_.cloud.header;
  in_camera.frame_id = scene::kCameraFrame;
  transform.translation().x() = 5.0;
  ASSERT_TRUE(rc::lookupSensorToCamera(tf_, in_camera, camera, kAtCloudStamp, transform).ok());
  EXPECT_TRUE(transform.isApprox(Eigen::Isometry3d::Identity()));

  std_msgs::Header unknown = set_.cloud.header;
  unknown.frame_id = "nowhere";
  const rc::ConversionStatus missing =
      rc::lookupSensorToCamera(tf_, unknown, camera, kAtCloudStamp, transform);
  EXPECT_EQ(missing.fault, InputFault::kTransformUnavailable);
  EXPECT_FALSE(missing.reason.empty());
}

TEST_F(DepthFrame, AFixedFrameCompensatesTheMotionBetweenTheCloudsAndTheImagesStamps) {
  // The camera drives 1 m along its optical axis between the cloud (stamp_) and the image
  // (stamp_ + 0.1 s): seen from the camera at the image's stamp the points are 1 m nearer.
  const auto odomToCamera = [](const ros::Time& stamp, double forward) {
    geometry_msgs::TransformStamped msg;
    msg.header.stamp = stamp;
    msg.header.frame_id = "odom";
    msg.child_frame_id = scene::kCameraFrame;
    msg.transform.translation.z = forward;
    msg.transform.rotation.w = 1.0;
    return msg;
  };
  const ros::Time image_stamp = stamp_ + ros::Duration(0.1);
  ASSERT_TRUE(tf_.setTransform(odomToCamera(stamp_ - ros::Duration(0.1), -1.0), "test"));
  ASSERT_TRUE(tf_.setTransform(odomToCamera(stamp_, 0.0), "test"));
  ASSERT_TRUE(tf_.setTransform(odomToCamera(image_stamp, 1.0), "test"));
  ASSERT_TRUE(tf_.setTransform(odomToCamera(image_stamp + ros::Duration(0.1), 2.0), "test"));

  Eigen::Isometry3d compensated, plain;
  const rc::CloudToCamera through_odom{ros::Duration(0.01), "odom"};
  ASSERT_TRUE(rc::lookupSensorToCamera(tf_, set_.cloud.header, cameraHeader(image_stamp),
                                       through_odom, compensated)
                  .ok());
  ASSERT_TRUE(rc::lookupSensorToCamera(tf_, set_.cloud.header, cameraHeader(image_stamp),
                                       kAtCloudStamp, plain)
                  .ok());
  EXPECT_LT(largestDifference(plain, scene::sensorToCamera()), 1e-9);  // the cloud's stamp only
  const Eigen::Isometry3d want = Eigen::Translation3d(0.0, 0.0, -1.0) * scene::sensorToCamera();
  EXPECT_LT(largestDifference(compensated, want), 1e-9) << compensated.matrix();

  // Points in the camera's own frame move too; equal stamps need no lookup at all.
  std_msgs::Header in_camera = set_.cloud.header;
  in_camera.frame_id = scene::kCameraFrame;
  ASSERT_TRUE(
      rc::lookupSensorToCamera(tf_, in_camera, cameraHeader(image_stamp), through_odom, compensated)
          .ok());
  EXPECT_NEAR(compensated.translation().z(), -1.0, 1e-9);
  ASSERT_TRUE(
      rc::lookupSensorToCamera(tf_, in_camera, cameraHeader(stamp_), through_odom, compensated)
          .ok());
  EXPECT_LT(largestDifference(compensated, Eigen::Isometry3d::Identity()), 1e-12);

  // A fixed frame tf does not know is a missing transform, named as such.
  const rc::CloudToCamera nowhere{ros::Duration(0.01), "map"};
  const rc::ConversionStatus missing = rc::lookupSensorToCamera(
      tf_, set_.cloud.header, cameraHeader(image_stamp), nowhere, compensated);
  EXPECT_EQ(missing.fault, InputFault::kTransformUnavailable);
}

TEST_F(DepthFrame, CompletesTheSceneAsTheCoreDoes) {
  const rc::DepthFrameResult result = complete();
  ASSERT_TRUE(result.completed()) << result.status.reason << result.error;
  EXPECT_EQ(result.reading.cap, mm::kLinearModelPointCap);
  EXPECT_EQ(result.reading.step, 1u);
  EXPECT_EQ(result.intrinsics.fx, scene::kFx);

  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& p : scene::sensorPoints())
    points.push_back(scene::sensorToCamera() * p.cast<float>().cast<double>());
  const mm::DepthMap want = mm::DepthCompleter(settings_.params.threads)
                                .complete(points, result.intrinsics,
                                          {{scene::kHeight, scene::kWidth}, 4}, settings_.params);
  const mm::DepthMap& got = workspace_.depth();
  EXPECT_EQ(got.depth, want.depth);
  EXPECT_EQ(got.variance, want.variance);
  EXPECT_EQ(got.valid, want.valid);
  EXPECT_GT(got.stats.kept, 0);
}

TEST_F(DepthFrame, TheCloudsTfOriginIsTheScannersPositionForTheHiddenReturnFilter) {
  // The scene's sensor sits 0.3 m below and 0.5 m behind the camera, so it sees under the box's
  // lower edge onto the wall: wall returns at camera rows 165 and 166 (the box spans rows
  // 100-170, its own returns lie on rows 160 and 168) are the sensor's, not the camera's.
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& p : scene::sensorPoints())
    points.push_back(scene::sensorToCamera() * p);
  for (int v : {165, 166}) {
    for (int u = 112; u <= 208; u += 4) {
      const double z = scene::kWallDepth;
      points.emplace_back((u - scene::kCx) / scene::kFx * z, (v - scene::kCy) / scene::kFy * z, z);
    }
  }
  std::vector<float> values;
  const Eigen::Isometry3d camera_to_sensor = scene::sensorToCamera().inverse();
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d q = camera_to_sensor * p;
    values.insert(values.end(), {float(q.x()), float(q.y()), float(q.z()), 1.f});
  }
  set_.cloud = rc::float32Cloud({"x", "y", "z", "intensity"}, values, set_.cloud.header);
  for (Eigen::Vector3d& p : points)  // what the node reads: the float32 cloud, transformed
    p = scene::sensorToCamera() * (camera_to_sensor * p).cast<float>().cast<double>();

  settings_.params.model = mm::DepthModel::kGroundGp;
  settings_.params.ground.input = mm::GroundPriorParams::Input::kDense;
  settings_.params.ground.drop_hidden_returns = true;
  settings_.stride = 1;
  const rc::DepthFrameResult result = complete();
  ASSERT_TRUE(result.completed()) << result.status.reason << result.error;
  const auto core = [&](bool with_origin) {
    mm::DepthCompletionParams params = settings_.params;
    if (with_origin) mm::setScanOrigin(scene::sensorToCamera().translation(), params.ground);
    return mm::DepthCompleter(params.threads)
        .complete(points, result.intrinsics, {{scene::kHeight, scene::kWidth}, 1}, params);
  };
  const mm::DepthMap want = core(true);
  EXPECT_EQ(workspace_.depth().depth, want.depth);
  EXPECT_EQ(workspace_.depth().variance, want.variance);
  // Without the origin the wall returns stay and the box's pixels between rows 160 and 168 take
  // the wall's depth; with it they keep the box's.
  const mm::DepthMap unfiltered = core(false);
  int wall_with = 0, wall_without = 0;
  for (int v = 161; v < 168; ++v) {
    for (int u = 120; u < 200; ++u) {
      const std::size_t p = std::size_t(v) * scene::kWidth + u;
      wall_with += want.depth[p] > 0.5 * (scene::kBoxDepth + scene::kWallDepth);
      wall_without += unfiltered.depth[p] > 0.5 * (scene::kBoxDepth + scene::kWallDepth);
    }
  }
  EXPECT_EQ(wall_with, 0);
  EXPECT_GT(wall_without, 100);
}

TEST_F(DepthFrame, ACloudOverTheCapIsReadEveryKthPoint) {
  const std::size_t total = scene::sensorPoints().size();
  const rc::DepthFrameResult result = complete(100);
  ASSERT_TRUE(result.completed()) << result.status.reason;
  EXPECT_EQ(result.reading.cap, 100u);
  const std::size_t step = (total + 99) / 100;
  EXPECT_EQ(result.reading.step, step);
  EXPECT_EQ(workspace_.depth().stats.points_total, (total + step - 1) / step);
}

TEST_F(DepthFrame, FaultsAreReportedInInputOrderWithTheirInput) {
  set_.info.K.fill(0.0);
  set_.cloud.point_step = 0;
  set_.cloud.header.frame_id = "nowhere";
  rc::DepthFrameResult result = complete();
  EXPECT_EQ(result.status.fault, InputFault::kCameraInfoIntrinsics);
  EXPECT_STREQ(result.input, "camera_info");

  set_.info = scene::cameraInfo(stamp_);
  result = complete();  // a malformed cloud, not a missing transform
  EXPECT_EQ(result.status.fault, InputFault::kCloudFieldOffset);
  EXPECT_STREQ(result.input, "points");

  set_.cloud.point_step = 16;
  result = complete();
  EXPECT_EQ(result.status.fault, InputFault::kTransformUnavailable);
  EXPECT_STREQ(result.input, "tf");
  EXPECT_FALSE(result.completed());
}

TEST_F(DepthFrame, ACloudBehindTheCameraNeverReachesTheModel) {
  set_.cloud.header.frame_id = scene::kCameraFrame;  // no transform: z as written below
  for (std::size_t i = 0; i < set_.cloud.width; ++i) {
    float z = -1.0f;
    std::memcpy(&set_.cloud.data[i * set_.cloud.point_step + 8], &z, sizeof z);
  }
  const rc::DepthFrameResult result = complete(10);
  EXPECT_EQ(result.status.fault, InputFault::kCloudBehindCamera);
  EXPECT_STREQ(result.input, "points");
  EXPECT_EQ(result.reading.step, 1u);  // nothing was subsampled for the model
}

TEST_F(DepthFrame, TheCoresInputErrorIsReportedApartFromInputFaults) {
  settings_.params.radius_deg = -1.0;
  const rc::DepthFrameResult result = complete();
  EXPECT_TRUE(result.status.ok());
  EXPECT_FALSE(result.error.empty());
  EXPECT_FALSE(result.completed());
}

}  // namespace
