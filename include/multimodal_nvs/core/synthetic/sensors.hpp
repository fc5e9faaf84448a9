#pragma once
// The sensors of the synthetic street: a car carrying a camera, a radar and a LiDAR with known
// extrinsics along a smooth drive, and how each sensor sees the scene (exact camera depth; radar
// and LiDAR returns with range/angle noise, dropouts and clutter).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/synthetic/street_scene.hpp"

namespace multimodal_nvs {
namespace synthetic {

/// Sensor mounts in the vehicle body frame B (on the ground below the camera: x forward, y left,
/// z up). The camera uses OpenCV axes (x right, y down, z forward); radar and LiDAR use x forward,
/// y left, z up like the View-of-Delft sensors.
struct SensorRig {
  Eigen::Isometry3d camera_in_body;
  Eigen::Isometry3d radar_in_body;
  Eigen::Isometry3d lidar_in_body;

  /// Camera `camera_height` m above the ground, its optical axis `camera_pitch_deg` above the
  /// horizon (positive: looking up, the convention of the `ground_pitch_deg` parameter); radar at
  /// the front bumper (1.6 m ahead, 0.2 m right, 0.5 m high, pitched 2 deg up); LiDAR on the roof
  /// (0.3 m behind, 0.6 m above the camera, level, yawed 1 deg).
  static SensorRig standard(double camera_height = 1.3, double camera_pitch_deg = 0.0);

  /// KITTI `Tr_velo_to_cam` of each sensor (sensor -> camera).
  SensorToCamera radarToCamera() const;
  SensorToCamera lidarToCamera() const;
};

/// View-of-Delft camera (1936 x 1216, f = 1495.5 px) scaled by `scale` (size rounded).
struct CameraModel {
  PinholeIntrinsics intrinsics;
  ImageSize size;
  static CameraModel vod(double scale = 1.0);
};

/// A smooth drive along the street: constant speed in the right lane with a gentle sideways sway
/// (the heading follows the path), sampled at `frame_interval_s`.
struct DrivePath {
  double start_x = 0.0;
  double speed = 4.0;    ///< m/s
  double lane_y = -1.5;  ///< lane centre (right-hand traffic: y < 0)
  double sway = 0.35;    ///< amplitude of the sideways sway (m)
  double sway_period_s = 9.0;
  double frame_interval_s = 0.1;  ///< 10 Hz like View-of-Delft

  /// World pose of the body frame at time t (s).
  Eigen::Isometry3d bodyPose(double t) const;
};

struct CameraImage {
  cv::Mat bgr;    ///< CV_8UC3, OpenCV channel order
  cv::Mat depth;  ///< CV_32FC1 camera z in metres at each pixel centre; 0 where the sky is seen
};

/// Ray-casts one image. Pixel (u, v) looks along K^-1 [u, v, 1] (integer pixel centres). Colour
/// averages `supersample` x `supersample` rays per pixel; depth comes from the centre ray.
CameraImage renderCamera(const SyntheticScene& scene, const CameraModel& camera,
                         const Eigen::Isometry3d& camera_to_world, int supersample,
                         ThreadPool& pool);

/// The range of a multipath ghost, as a factor of the surface's range: at least the first, and
/// RadarParams::ghost_range_factor_max may be at most the second.
constexpr double kMinGhostRangeFactor = 1.1;
constexpr double kMaxGhostRangeFactor = 10.0;

struct RadarParams {
  int candidates = 1600;          ///< random beam directions tried per scan
  double azimuth_fov_deg = 60.0;  ///< +- field of view
  double elevation_min_deg = -8.0;
  double elevation_max_deg = 12.0;
  double min_range = 0.8;
  double max_range = 80.0;
  double azimuth_cell_deg = 1.0;  ///< resolution cells: one detection per cell at most
  double elevation_cell_deg = 2.0;
  double range_cell = 0.25;   ///< m
  double range_sigma = 0.10;  ///< m
  double azimuth_sigma_deg = 0.25;
  double elevation_sigma_deg = 0.5;
  double velocity_sigma = 0.05;  ///< m/s
  double rcs_sigma_db = 3.0;
  double clutter_fraction = 0.05;  ///< share of all returns that are clutter (on no surface)
  /// Share of detections that come from the next surface behind the first one the beam meets
  /// (none where there is none: a ground hit is lost): a radar sees under vehicles and through
  /// foliage, and multipath returns arrive late. Real radar has about half of its returns 20 % or
  /// more behind the nearest LiDAR surface at their pixel (VoD 00549/01047 0.45, Astyx 0.51,
  /// nuScenes 0.42; scripts/radar_surface_offsets.py); the synthetic street 0.03-0.25 with 0,
  /// 0.27-0.42 with 0.9. 0 by default: the evaluation's scenes were made without it.
  double pass_through = 0.0;
  /// Share of detections that are multipath ghosts: the echo came back over a longer path (via a
  /// second reflector), so the detection lies along the beam at a range factor uniform in
  /// [kMinGhostRangeFactor, ghost_range_factor_max] times the surface's range, behind it and on no
  /// surface. 0 by default (see pass_through).
  double ghosts = 0.0;
  double ghost_range_factor_max = 2.0;
  /// false: a 2D radar (nuScenes' front radar, Continental ARS-class): it measures range and
  /// azimuth but not elevation, so every detection is reported on the radar's own horizontal
  /// plane (elevation 0) at its measured range and azimuth. The random sequence is the same.
  bool measures_elevation = true;
};

/// One radar return in the radar frame, as the VoD record x, y, z, RCS, v_r, v_r_compensated, time.
struct RadarReturn {
  Eigen::Vector3f position;
  float rcs = 0.f;
  float v_r = 0.f;
  float v_r_compensated = 0.f;
  float time = 0.f;
  bool clutter = false;     ///< not from a surface (simulation truth, not written to files)
  bool ghost = false;       ///< a multipath ghost behind the surface hit (simulation truth)
  double true_range = 0.0;  ///< noise-free range of the surface hit (0 for clutter)
};

/// Radar scan: beams in random directions, detected with a probability from the material,
/// incidence and range, at most one per resolution cell; range/azimuth/elevation noise; radial
/// velocities of the static world seen from the moving radar (`radar_velocity`: the radar's own
/// velocity in its frame).
std::vector<RadarReturn> simulateRadar(const SyntheticScene& scene,
                                       const Eigen::Isometry3d& radar_to_world,
                                       const Eigen::Vector3d& radar_velocity,
                                       const RadarParams& params, Random& rng);

struct LidarParams {
  int rings = 64;
  double elevation_max_deg = 2.0;  ///< HDL-64-like vertical field of view
  double elevation_min_deg = -24.8;
  double azimuth_step_deg = 0.2;  ///< 1800 columns per turn
  double min_range = 1.0;
  double max_range = 120.0;
  double range_sigma = 0.02;  ///< m
  double dropout = 0.02;      ///< probability that a return is missing

  /// The rings and vertical field of view of a Velodyne with `beams` = 16 (VLP-16, +-15 deg),
  /// 32 (HDL-32E, +10.67..-30.67 deg) or 64 (HDL-64E, the defaults); other counts throw
  /// InputError.
  static LidarParams velodyne(int beams);
};

/// One LiDAR return in the LiDAR frame; intensity 0..255 like VoD.
struct LidarReturn {
  Eigen::Vector3f position;
  float intensity = 0.f;
};

/// A full 360 deg LiDAR turn (column by column, rings bottom to top within a column).
/// Deterministic for a given `seed` and independent of the pool size.
std::vector<LidarReturn> simulateLidar(const SyntheticScene& scene,
                                       const Eigen::Isometry3d& lidar_to_world,
                                       const LidarParams& params, std::uint64_t seed,
                                       ThreadPool& pool);

}  // namespace synthetic
}  // namespace multimodal_nvs
