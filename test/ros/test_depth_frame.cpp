// completeDepthFrame and its steps on the synthetic scene: the sensor -> camera transform (at the
// cloud's stamp, or across the two stamps through a fixed frame), the ground plane from tf, the
// point cap, the order in which faults are reported, the core's result unchanged; no master.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
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

/// The scene's points as the node reads them: float32 in the cloud, then into the camera frame.
std::vector<Eigen::Vector3d> pointsAsTheNodeReadsThem() {
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& p : scene::sensorPoints())
    points.push_back(scene::sensorToCamera() * p.cast<float>().cast<double>());
  return points;
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

  rc::DepthFrameResult complete(int max_points = 0, const rc::GroundFromTf& ground = {}) {
    return rc::completeDepthFrame(set_.cloud, image_, set_.info, tf_, kAtCloudStamp, ground,
                                  settings_, max_points, workspace_);
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

  const std::vector<Eigen::Vector3d> points = pointsAsTheNodeReadsThem();
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

/// The camera's optical frame (x right, y down, z forward) in a z-up frame on the road under it:
/// `height` above the road, the optical axis `pitch_deg` above the horizon.
Eigen::Isometry3d cameraToGround(double height, double pitch_deg) {
  Eigen::Matrix3d optical_to_level;  // columns: the optical axes in a level x-forward, z-up frame
  optical_to_level << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() =
      Eigen::AngleAxisd(-pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix() *
      optical_to_level;
  t.translation() = Eigen::Vector3d(0.0, 0.0, height);
  return t;
}

geometry_msgs::TransformStamped groundToCameraMsg(const Eigen::Isometry3d& camera_to_ground) {
  geometry_msgs::TransformStamped msg = tf2::eigenToTransform(camera_to_ground);
  msg.header.frame_id = "scene_base_footprint";
  msg.child_frame_id = scene::kCameraFrame;
  return msg;
}

TEST_F(DepthFrame, TheGroundPlaneComesFromTfWhenAGroundFrameIsSet) {
  const Eigen::Isometry3d camera_to_ground = cameraToGround(1.7, 5.0);
  ASSERT_TRUE(tf_.setTransform(groundToCameraMsg(camera_to_ground), "test", /*is_static=*/true));
  const rc::GroundFromTf from_tf{"scene_base_footprint", ros::Duration(0.01)};

  mm::GroundPriorParams ground;  // the parameters: 1.3 m, level
  ASSERT_TRUE(rc::lookupGroundPlane(tf_, cameraHeader(stamp_), from_tf, ground).ok());
  EXPECT_NEAR(ground.camera_height, 1.7, 1e-9);
  // World up seen from the camera: mostly -y (image up); the optical axis points 5 deg above the
  // horizon, so up has a component sin(5 deg) along it.
  const Eigen::Vector3d up = camera_to_ground.linear().transpose() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(ground.up_x, up.x(), 1e-9);
  EXPECT_NEAR(ground.up_y, up.y(), 1e-9);
  EXPECT_NEAR(ground.up_z, up.z(), 1e-9);
  EXPECT_NEAR(ground.up_y, -std::cos(5.0 * M_PI / 180.0), 1e-9);
  EXPECT_NEAR(ground.up_z, std::sin(5.0 * M_PI / 180.0), 1e-9);
  EXPECT_EQ(ground.plane_source, mm::GroundPriorParams::PlaneSource::kPose);

  // No ground frame: the parameters stay as they are.
  mm::GroundPriorParams untouched;
  ASSERT_TRUE(rc::lookupGroundPlane(tf_, cameraHeader(stamp_), {}, untouched).ok());
  EXPECT_EQ(untouched.camera_height, mm::GroundPriorParams().camera_height);
  EXPECT_EQ(untouched.plane_source, mm::GroundPriorParams::PlaneSource::kParameters);

  // A ground frame tf does not know is a missing transform that names the frame.
  const rc::ConversionStatus missing = rc::lookupGroundPlane(
      tf_, cameraHeader(stamp_), {"base_footprint", ros::Duration(0.01)}, untouched);
  EXPECT_EQ(missing.fault, InputFault::kTransformUnavailable);
  EXPECT_NE(missing.reason.find("base_footprint"), std::string::npos) << missing.reason;
  EXPECT_EQ(untouched.camera_height, mm::GroundPriorParams().camera_height);
}

TEST_F(DepthFrame, AModelWithAGroundPlaneTakesItFromTfAndTheCoreComputesTheSame) {
  const Eigen::Isometry3d camera_to_ground = cameraToGround(1.7, 5.0);
  ASSERT_TRUE(tf_.setTransform(groundToCameraMsg(camera_to_ground), "test", /*is_static=*/true));
  settings_.params.model = mm::DepthModel::kGroundGp;
  const rc::GroundFromTf from_tf{"scene_base_footprint", ros::Duration(0.01)};
  const rc::DepthFrameResult result = complete(0, from_tf);
  ASSERT_TRUE(result.completed()) << result.status.reason << result.error;
  const mm::DepthMap got = workspace_.depth();
  EXPECT_EQ(got.stats.ground_source, "pose");
  // The stats report the plane that ran (depth/stats, diagnostics).
  EXPECT_NEAR(got.stats.ground_camera_height, 1.7, 1e-6);
  EXPECT_NEAR(got.stats.ground_pitch_deg, 5.0, 1e-6);
  EXPECT_NEAR(got.stats.ground_roll_deg, 0.0, 1e-6);

  const std::vector<Eigen::Vector3d> points = pointsAsTheNodeReadsThem();
  mm::DepthCompletionParams params = settings_.params;
  mm::applyCameraPose(camera_to_ground.matrix(), params.ground);
  const mm::DepthMap want =
      mm::DepthCompleter(params.threads)
          .complete(points, result.intrinsics, {{scene::kHeight, scene::kWidth}, 4}, params);
  EXPECT_EQ(got.depth, want.depth);
  EXPECT_EQ(got.variance, want.variance);

  // The parameters' plane (1.3 m, level) gives another depth: the plane did reach the model.
  ASSERT_TRUE(complete().completed());
  EXPECT_EQ(workspace_.depth().stats.ground_source, "parameters");
  EXPECT_NEAR(workspace_.depth().stats.ground_camera_height, settings_.params.ground.camera_height,
              1e-9);
  EXPECT_NEAR(workspace_.depth().stats.ground_pitch_deg, 0.0, 1e-9);
  EXPECT_NE(workspace_.depth().depth, got.depth);
}

TEST_F(DepthFrame, AMissingGroundTransformDropsOnlyTheModelsThatUseTheGround) {
  const rc::GroundFromTf nowhere{"base_footprint", ros::Duration(0.01)};
  settings_.params.model = mm::DepthModel::kGroundGp;
  const rc::DepthFrameResult dropped = complete(0, nowhere);
  EXPECT_EQ(dropped.status.fault, InputFault::kTransformUnavailable);
  EXPECT_STREQ(dropped.input, "tf");
  EXPECT_FALSE(dropped.completed());
  settings_.params.model = mm::DepthModel::kKernel;  // no ground plane: no lookup
  const rc::DepthFrameResult kernel = complete(0, nowhere);
  EXPECT_TRUE(kernel.completed()) << kernel.status.reason;
}

TEST_F(DepthFrame, TheImageReachesTheModelsInTheCoresChannelOrder) {
  // A bright, flat, blue sky over rows 0-59 (above the horizon and every return): the core, given
  // the image in OpenCV's BGR order as the tools read it, sends it to the far clamp. Its colour
  // test reads the channels by position, so an image handed over in RGB order has no sky.
  for (int v = 0; v < 60; ++v) {
    for (int u = 0; u < scene::kWidth; ++u) {
      std::uint8_t* px = &set_.image.data[std::size_t(v) * set_.image.step + 3 * u];  // bgr8
      px[0] = 230;
      px[1] = 180;
      px[2] = 120;
    }
  }
  ASSERT_TRUE(rc::frameImage(set_.image, image_).ok());
  settings_.params.model = mm::DepthModel::kImageGuided;
  const rc::DepthFrameResult result = complete();
  ASSERT_TRUE(result.completed()) << result.status.reason << result.error;
  const mm::DepthMap got = workspace_.depth();

  const std::vector<Eigen::Vector3d> points = pointsAsTheNodeReadsThem();
  const cv::Mat bgr =
      cv::Mat(scene::kHeight, scene::kWidth, CV_8UC3, set_.image.data.data(), set_.image.step)
          .clone();
  const mm::DepthMap want =
      mm::DepthCompleter(settings_.params.threads)
          .complete(points, result.intrinsics, {{scene::kHeight, scene::kWidth}, 4},
                    settings_.params, bgr);
  EXPECT_EQ(got.depth, want.depth);
  EXPECT_EQ(got.variance, want.variance);
  const float far = static_cast<float>(settings_.params.guided.far_depth);
  const long sky = std::count(got.depth.begin(), got.depth.begin() + 15 * got.grid.cols(), far);
  // Grid rows 0-14 are image rows 0-56: sky but for the columns near the image's edge.
  EXPECT_GT(sky, 12 * got.grid.cols());

  // The same pixels as rgb8 give the same depth.
  sensor_msgs::Image rgb8 = set_.image;
  rgb8.encoding = sensor_msgs::image_encodings::RGB8;
  for (int v = 0; v < scene::kHeight; ++v) {
    for (int u = 0; u < scene::kWidth; ++u)
      std::swap(rgb8.data[std::size_t(v) * rgb8.step + 3 * u],
                rgb8.data[std::size_t(v) * rgb8.step + 3 * u + 2]);
  }
  ASSERT_TRUE(rc::frameImage(rgb8, image_).ok());
  ASSERT_TRUE(complete().completed());
  EXPECT_EQ(workspace_.depth().depth, got.depth);
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
