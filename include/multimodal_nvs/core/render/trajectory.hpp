#pragma once
// Target views: recorded poses resampled to GEN3C's frame count, and preset camera paths.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"

namespace multimodal_nvs {

/// One target view: world-to-camera where "world" is the reference camera's frame (the frame of
/// the coloured cloud), and the intrinsics at the render size.
struct TargetCamera {
  Eigen::Matrix4d world_to_camera = Eigen::Matrix4d::Identity();
  PinholeIntrinsics intrinsics;
};

/// The views a conditioning video is rendered from. Frame 0 is the reference view.
struct Trajectory {
  ImageSize size;
  std::vector<TargetCamera> cameras;
  /// Frame indices where the recorded poses land (0, 8, ..., 120 for 16 poses into 121 frames);
  /// empty for presets. Ground truth is compared at these frames.
  std::vector<int> recorded_frames;
};

/// w2c_i = inv(T_i) T_0 for camera-to-world poses T (GEN3C's published renderer). Throws InputError
/// if empty.
std::vector<Eigen::Matrix4d> relativeWorldToCamera(
    const std::vector<Eigen::Matrix4d>& camera_to_world);

/// Camera-to-world pose a fraction t in [0, 1] of the way from a to b: rotation by SLERP, camera
/// centre linearly.
Eigen::Matrix4d interpolateCameraPose(const Eigen::Matrix4d& a_camera_to_world,
                                      const Eigen::Matrix4d& b_camera_to_world, double t);

/// The frames recorded pose j lands on: round(j (num_frames - 1) / (num_poses - 1)). Throws
/// InputError unless 1 <= num_poses <= num_frames (a single pose needs num_frames >= 1).
std::vector<int> recordedFrameIndices(int num_poses, int num_frames);

/// Recorded camera-to-world poses made relative to the first one and resampled to `num_frames`:
/// each segment between consecutive recorded frames is filled by SLERP + linear centre, so the
/// recorded poses are reproduced exactly at recordedFrameIndices(). `intrinsics` (at the render
/// size) is shared by every frame.
Trajectory recordedTrajectory(const std::vector<Eigen::Matrix4d>& camera_to_world, int num_frames,
                              const PinholeIntrinsics& intrinsics, ImageSize size);

enum class TrajectoryPreset {
  kForward,
  kBackward,
  kLeft,
  kRight,
  kUp,
  kDown,
  kOrbitLeft,
  kOrbitRight,
  kZoomIn,
  kZoomOut,
};

/// Parses "forward", "orbit_left", ...; throws InputError listing the valid names.
TrajectoryPreset parseTrajectoryPreset(const std::string& name);
std::string toString(TrajectoryPreset preset);
/// "m" for translations, "deg" for orbits (arc angle) and zooms (change of horizontal field of
/// view).
std::string magnitudeUnit(TrajectoryPreset preset);

/// A synthetic trajectory that moves linearly from the reference view (frame 0) to `magnitude` at
/// the last frame. Translations move the camera along its own axes (x right, y down, z forward);
/// orbits turn the camera about the vertical axis through (0, 0, orbit_centre_depth) while keeping
/// that point centred; zooms change the focal length so that the horizontal field of view narrows
/// (zoom_in) or widens (zoom_out) by `magnitude` degrees without moving the camera. Throws
/// InputError for a non-finite or negative magnitude, a non-positive orbit depth, or a zoom that
/// leaves (0, 180) degrees.
Trajectory presetTrajectory(TrajectoryPreset preset, double magnitude, int num_frames,
                            const PinholeIntrinsics& intrinsics, ImageSize size,
                            double orbit_centre_depth);

}  // namespace multimodal_nvs
