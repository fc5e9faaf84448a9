#pragma once
// The synthetic street as a View-of-Delft recording: frames of camera, radar, LiDAR and poses along
// the drive, written in the VoD layout (View-of-Delft's dataset layout) plus exact depth ground
// truth:
//   ROOT/lidar/training/{image_2/NNNNN.jpg, velodyne/NNNNN.bin, calib/NNNNN.txt, pose/NNNNN.json}
//   ROOT/radar/training/{velodyne/NNNNN.bin, calib/NNNNN.txt}
//   ROOT/depth_gt/NNNNN.npy   float32 H x W camera z (m), 0 where the sky is seen
//   ROOT/scene.json           the generator's parameters
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "multimodal_nvs/core/synthetic/sensors.hpp"
#include "multimodal_nvs/core/synthetic/street_scene.hpp"

namespace multimodal_nvs {
namespace synthetic {

struct SyntheticDatasetParams {
  std::uint64_t seed = 1;
  int frames = 16;
  int first_frame = 0;  ///< number of the first frame's files
  double scale = 1.0;   ///< image size and intrinsics relative to the VoD camera
  int supersample = 0;  ///< rays per pixel per axis for colour; 0: 2 when scale <= 0.5, else 1
  int jpeg_quality = 95;
  int threads = 0;                ///< 0: all cores
  double camera_height = 1.3;     ///< m above the road
  double camera_pitch_deg = 0.0;  ///< optical axis above the horizon (positive: looking up)
  int extra_vehicles = 0;         ///< occluders along the drive, see StreetLayout
  int pedestrians = 0;
  int extra_poles = 0;
  DrivePath path;
  RadarParams radar;
  LidarParams lidar;

  /// Throws InputError naming the parameter when a value is out of range.
  void validate() const;
  int effectiveSupersample() const;
};

/// Everything one frame holds in memory (poses in the scene's world frame, which is `odom`).
struct SyntheticFrame {
  int number = 0;  ///< file number (first_frame + index)
  CameraImage camera;
  std::vector<RadarReturn> radar;  ///< radar frame
  std::vector<LidarReturn> lidar;  ///< LiDAR frame
  Eigen::Isometry3d camera_to_odom = Eigen::Isometry3d::Identity();
};

class SyntheticDataset {
 public:
  explicit SyntheticDataset(const SyntheticDatasetParams& params);
  ~SyntheticDataset();

  const SyntheticDatasetParams& params() const { return params_; }
  const SyntheticScene& scene() const { return *scene_; }
  const SensorRig& rig() const { return rig_; }
  const CameraModel& camera() const { return camera_; }

  /// Camera pose (camera -> odom, OpenCV axes) of frame `index` (0-based).
  Eigen::Isometry3d cameraToOdom(int index) const;
  /// The fixed transforms behind the `mapToCamera` and `UTMToCamera` poses.
  static Eigen::Isometry3d mapFromOdom();
  static Eigen::Isometry3d utmFromMap();

  /// Renders and simulates frame `index` (0-based); deterministic for the seed.
  SyntheticFrame frame(int index) const;

  /// Writes all frames in the VoD layout under `root` (directories created). `progress` is called
  /// after each frame with (frames done, frames total). Throws InputError when a file cannot be
  /// written.
  void write(const std::string& root,
             const std::function<void(int, int)>& progress = std::function<void(int, int)>()) const;

  /// The three pose lines of a VoD pose file for a camera pose in odom.
  static std::string poseJson(const Eigen::Isometry3d& camera_to_odom);

 private:
  SyntheticDatasetParams params_;
  std::unique_ptr<SyntheticScene> scene_;
  SensorRig rig_;
  CameraModel camera_;
  std::unique_ptr<ThreadPool> pool_;
};

}  // namespace synthetic
}  // namespace multimodal_nvs
