// Trajectories: relative poses, SLERP resampling (16 -> 121), presets (GEN3C's published renderer).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"

namespace mm = multimodal_nvs;

namespace {

Eigen::Matrix4d pose(double yaw_deg, const Eigen::Vector3d& centre) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  m.topRightCorner<3, 1>() = centre;
  return m;
}

const mm::PinholeIntrinsics kK{100.0, 100.0, 64.0, 48.0};
const mm::ImageSize kSize{96, 128};

Eigen::Vector3d cameraCentre(const Eigen::Matrix4d& w2c) {
  return -w2c.topLeftCorner<3, 3>().transpose() * w2c.topRightCorner<3, 1>();
}

}  // namespace

TEST(Trajectory, RelativeToFirstPose) {
  const std::vector<Eigen::Matrix4d> c2w{pose(30, {5, 1, -2}), pose(40, {6, 1, -2})};
  const auto w2c = mm::relativeWorldToCamera(c2w);
  EXPECT_TRUE(w2c[0].isApprox(Eigen::Matrix4d::Identity(), 1e-12));
  EXPECT_TRUE(w2c[1].isApprox(c2w[1].inverse() * c2w[0], 1e-12));
  EXPECT_THROW(mm::relativeWorldToCamera({}), mm::InputError);
}

TEST(Trajectory, SlerpEndpointsAndMidpoint) {
  const Eigen::Matrix4d a = pose(10, {0, 0, 0}), b = pose(100, {2, 0, 4});
  EXPECT_EQ(mm::interpolateCameraPose(a, b, 0.0), a);
  EXPECT_EQ(mm::interpolateCameraPose(a, b, 1.0), b);
  const Eigen::Matrix4d mid = mm::interpolateCameraPose(a, b, 0.5);
  EXPECT_TRUE(mid.isApprox(pose(55, {1, 0, 2}), 1e-12)) << mid;
  const Eigen::Matrix4d quarter = mm::interpolateCameraPose(a, b, 0.25);
  EXPECT_TRUE(quarter.isApprox(pose(32.5, {0.5, 0, 1}), 1e-12)) << quarter;
}

TEST(Trajectory, SixteenPosesLandOnEveryEighthOf121) {
  const std::vector<int> idx = mm::recordedFrameIndices(16, 121);
  ASSERT_EQ(idx.size(), 16u);
  for (int j = 0; j < 16; ++j)
    EXPECT_EQ(idx[static_cast<std::size_t>(j)], 8 * j);
  EXPECT_EQ(mm::recordedFrameIndices(1, 5), std::vector<int>{0});
  EXPECT_THROW(mm::recordedFrameIndices(16, 10), mm::InputError);
}

TEST(Trajectory, RecordedPosesReproducedAndSegmentsInterpolated) {
  std::vector<Eigen::Matrix4d> c2w;
  for (int j = 0; j < 16; ++j)
    c2w.push_back(pose(3.0 * j + 20, {0.2 * j + 7, -1.0, 0.5 * j}));
  const mm::Trajectory traj = mm::recordedTrajectory(c2w, 121, kK, kSize);
  ASSERT_EQ(traj.cameras.size(), 121u);
  EXPECT_EQ(traj.recorded_frames.back(), 120);
  EXPECT_EQ(traj.cameras[0].world_to_camera, Eigen::Matrix4d::Identity());
  const auto rel = mm::relativeWorldToCamera(c2w);
  for (int j = 0; j < 16; ++j) {
    EXPECT_TRUE(traj.cameras[static_cast<std::size_t>(8 * j)].world_to_camera.isApprox(
        rel[static_cast<std::size_t>(j)], 1e-12))
        << j;
  }
  // Frame 4 is halfway between recorded poses 0 and 1: half the yaw step and half the centre step
  // (the relative motion is a pure yaw and a translation in the reference frame).
  const Eigen::Matrix4d expected_c2w =
      mm::interpolateCameraPose(rel[0].inverse(), rel[1].inverse(), 0.5);
  EXPECT_TRUE(traj.cameras[4].world_to_camera.isApprox(expected_c2w.inverse(), 1e-12));
  EXPECT_EQ(traj.cameras[77].intrinsics.fx, kK.fx);
}

TEST(Trajectory, TranslationPresetsMoveAlongCameraAxes) {
  struct Case {
    const char* name;
    Eigen::Vector3d centre;
  };
  for (const Case& c :
       {Case{"forward", {0, 0, 2}}, Case{"backward", {0, 0, -2}}, Case{"left", {-2, 0, 0}},
        Case{"right", {2, 0, 0}}, Case{"up", {0, -2, 0}}, Case{"down", {0, 2, 0}}}) {
    const mm::Trajectory t =
        mm::presetTrajectory(mm::parseTrajectoryPreset(c.name), 2.0, 5, kK, kSize, 10.0);
    EXPECT_EQ(t.cameras.front().world_to_camera, Eigen::Matrix4d::Identity()) << c.name;
    EXPECT_TRUE(cameraCentre(t.cameras.back().world_to_camera).isApprox(c.centre, 1e-12)) << c.name;
    EXPECT_TRUE(cameraCentre(t.cameras[2].world_to_camera).isApprox(0.5 * c.centre, 1e-12));
    EXPECT_EQ(mm::magnitudeUnit(mm::parseTrajectoryPreset(c.name)), "m");
  }
}

TEST(Trajectory, OrbitKeepsCentreOnOpticalAxis) {
  for (const char* name : {"orbit_left", "orbit_right"}) {
    const mm::Trajectory t =
        mm::presetTrajectory(mm::parseTrajectoryPreset(name), 30.0, 7, kK, kSize, 12.0);
    for (const mm::TargetCamera& cam : t.cameras) {
      const Eigen::Vector4d p = cam.world_to_camera * Eigen::Vector4d(0, 0, 12, 1);
      EXPECT_NEAR(p.x(), 0.0, 1e-9);
      EXPECT_NEAR(p.y(), 0.0, 1e-9);
      EXPECT_NEAR(p.z(), 12.0, 1e-9);  // distance to the centre is kept
    }
    const Eigen::Vector3d c = cameraCentre(t.cameras.back().world_to_camera);
    EXPECT_NEAR(std::abs(c.x()), 12.0 * std::sin(M_PI / 6), 1e-9);
    EXPECT_EQ(c.x() < 0, std::string(name) == "orbit_left") << name;
  }
  EXPECT_THROW(mm::presetTrajectory(mm::TrajectoryPreset::kOrbitLeft, 10, 3, kK, kSize, 0.0),
               mm::InputError);
}

TEST(Trajectory, ZoomChangesFieldOfViewOnly) {
  const double fov0 = 2 * std::atan(64.0 / 100.0) * 180 / M_PI;
  const mm::Trajectory in =
      mm::presetTrajectory(mm::TrajectoryPreset::kZoomIn, 10.0, 3, kK, kSize, 1);
  const double fov_in = 2 * std::atan(64.0 / in.cameras.back().intrinsics.fx) * 180 / M_PI;
  EXPECT_NEAR(fov_in, fov0 - 10.0, 1e-9);
  EXPECT_EQ(in.cameras.back().world_to_camera, Eigen::Matrix4d::Identity());
  EXPECT_EQ(in.cameras.back().intrinsics.cx, kK.cx);
  const mm::Trajectory out =
      mm::presetTrajectory(mm::TrajectoryPreset::kZoomOut, 10.0, 3, kK, kSize, 1);
  EXPECT_LT(out.cameras.back().intrinsics.fx, kK.fx);
  EXPECT_THROW(mm::presetTrajectory(mm::TrajectoryPreset::kZoomIn, 180.0, 3, kK, kSize, 1),
               mm::InputError);
}

TEST(Trajectory, PresetErrors) {
  EXPECT_THROW(mm::parseTrajectoryPreset("sideways"), mm::InputError);
  EXPECT_THROW(mm::presetTrajectory(mm::TrajectoryPreset::kForward, -1.0, 3, kK, kSize, 1),
               mm::InputError);
  EXPECT_THROW(mm::presetTrajectory(mm::TrajectoryPreset::kForward, 1.0, 0, kK, kSize, 1),
               mm::InputError);
  for (const char* name : {"forward", "backward", "left", "right", "up", "down", "orbit_left",
                           "orbit_right", "zoom_in", "zoom_out"}) {
    EXPECT_EQ(mm::toString(mm::parseTrajectoryPreset(name)), name);
  }
}
