#include "multimodal_nvs/core/synthetic/dataset.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace multimodal_nvs {
namespace synthetic {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("synthetic scene parameter " + what);
}

void makeDirectories(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec) throw InputError(path + ": cannot create directory (" + ec.message() + ")");
}

std::string matrixJson(const Eigen::Matrix4d& m) {
  std::string out = "[";
  char buf[40];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof buf, "%.17g", m(r, c));
      out += buf;
      if (r != 3 || c != 3) out += ", ";
    }
  }
  return out + "]";
}

Eigen::Isometry3d yawTranslation(double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).matrix();
  pose.translation() = t;
  return pose;
}

}  // namespace

void SyntheticDatasetParams::validate() const {
  require(frames >= 1, "frames must be >= 1");
  require(first_frame >= 0 && first_frame + frames - 1 <= 99999,
          "first-frame: frame numbers must stay within 0..99999");
  require(scale > 0.0 && scale <= 4.0, "scale must be in (0, 4]");
  require(supersample >= 0 && supersample <= 8, "supersample must be in 0..8");
  require(jpeg_quality >= 1 && jpeg_quality <= 100, "jpeg-quality must be in 1..100");
  require(std::isfinite(path.speed) && path.speed >= 0.0 && path.speed <= 40.0,
          "speed must be in [0, 40] m/s");
  require(path.frame_interval_s > 0.0, "frame interval must be positive");
  require(radar.candidates >= 0 && radar.clutter_fraction >= 0.0 && radar.clutter_fraction < 0.9,
          "radar: candidates >= 0 and clutter fraction in [0, 0.9)");
  require(radar.range_sigma >= 0 && radar.azimuth_sigma_deg >= 0 && radar.elevation_sigma_deg >= 0,
          "radar noise must be >= 0");
  require(radar.pass_through >= 0.0 && radar.pass_through <= 1.0,
          "radar: pass-through share in [0, 1]");
  require(radar.ghosts >= 0.0 && radar.ghosts <= 1.0 &&
              radar.ghost_range_factor_max >= kMinGhostRangeFactor &&
              radar.ghost_range_factor_max <= kMaxGhostRangeFactor,
          "radar: ghost share in [0, 1] and ghost range factor in [1.1, 10]");
  require(lidar.rings >= 1 && lidar.azimuth_step_deg > 0.01 && lidar.range_sigma >= 0,
          "lidar: rings >= 1, azimuth step > 0.01 deg, noise >= 0");
  require(std::isfinite(camera_height) && camera_height >= 0.3 && camera_height <= 5.0,
          "camera height must be in [0.3, 5] m");
  require(std::isfinite(camera_pitch_deg) && std::abs(camera_pitch_deg) <= 30.0,
          "camera pitch must be in [-30, 30] deg");
  require(extra_vehicles >= 0 && extra_vehicles <= 200 && pedestrians >= 0 && pedestrians <= 500 &&
              extra_poles >= 0 && extra_poles <= 500,
          "occluders: vehicles 0..200, pedestrians and poles 0..500");
}

int SyntheticDatasetParams::effectiveSupersample() const {
  if (supersample > 0) return supersample;
  return scale <= 0.5 ? 2 : 1;
}

SyntheticDataset::SyntheticDataset(const SyntheticDatasetParams& params)
    : params_(params),
      rig_(SensorRig::standard(params.camera_height, params.camera_pitch_deg)),
      camera_(CameraModel::vod(params.scale)) {
  params_.validate();
  StreetLayout layout;
  // The street reaches well beyond the end of the drive.
  const double drive_end =
      params_.path.start_x + params_.path.speed * params_.path.frame_interval_s * params_.frames;
  layout.length = std::max(layout.length, drive_end - layout.start_x + 220.0);
  // Occluders where the cameras look: from just ahead of the start to 70 m beyond the end, out
  // of the ego lane until 8 m past the drive's end (the car body's front is 1.6 m ahead).
  layout.extra_vehicles = params_.extra_vehicles;
  layout.pedestrians = params_.pedestrians;
  layout.extra_poles = params_.extra_poles;
  layout.occluder_min_x = params_.path.start_x + 4.0;
  layout.occluder_max_x = drive_end + 70.0;
  layout.ego_lane_clear_until_x = drive_end + 8.0;
  scene_ = std::make_unique<SyntheticScene>(params_.seed, layout);
  pool_ = std::make_unique<ThreadPool>(params_.threads);
}

SyntheticDataset::~SyntheticDataset() = default;

Eigen::Isometry3d SyntheticDataset::cameraToOdom(int index) const {
  const double t = index * params_.path.frame_interval_s;
  return params_.path.bodyPose(t) * rig_.camera_in_body;
}

Eigen::Isometry3d SyntheticDataset::mapFromOdom() {
  return yawTranslation(0.004, Eigen::Vector3d(-751.25, 1024.5, 0.0));
}

Eigen::Isometry3d SyntheticDataset::utmFromMap() {
  return yawTranslation(-0.0196, Eigen::Vector3d(594622.75, 5761496.5, 0.0));
}

std::string SyntheticDataset::poseJson(const Eigen::Isometry3d& camera_to_odom) {
  const Eigen::Isometry3d map = mapFromOdom() * camera_to_odom;
  const Eigen::Isometry3d utm = utmFromMap() * map;
  return "{\"odomToCamera\": " + matrixJson(camera_to_odom.matrix()) + "}\n" +
         "{\"mapToCamera\": " + matrixJson(map.matrix()) + "}\n" +
         "{\"UTMToCamera\": " + matrixJson(utm.matrix()) + "}\n";
}

SyntheticFrame SyntheticDataset::frame(int index) const {
  SyntheticFrame f;
  f.number = params_.first_frame + index;
  f.camera_to_odom = cameraToOdom(index);
  f.camera =
      renderCamera(*scene_, camera_, f.camera_to_odom, params_.effectiveSupersample(), *pool_);

  const double t = index * params_.path.frame_interval_s;
  const Eigen::Isometry3d body = params_.path.bodyPose(t);
  const Eigen::Isometry3d radar_to_world = body * rig_.radar_in_body;
  // The radar's own velocity (includes the lever arm of the turning car), in the radar frame.
  const double h = 1e-3;
  const Eigen::Vector3d ahead = (params_.path.bodyPose(t + h) * rig_.radar_in_body).translation();
  const Eigen::Vector3d behind = (params_.path.bodyPose(t - h) * rig_.radar_in_body).translation();
  const Eigen::Vector3d velocity =
      radar_to_world.linear().transpose() * ((ahead - behind) / (2 * h));
  Random radar_rng = Random::derived(params_.seed, 0x7ada7, static_cast<std::uint64_t>(index));
  f.radar = simulateRadar(*scene_, radar_to_world, velocity, params_.radar, radar_rng);

  const std::uint64_t lidar_seed =
      Random::derived(params_.seed, 0x11da7, static_cast<std::uint64_t>(index)).next();
  f.lidar = simulateLidar(*scene_, body * rig_.lidar_in_body, params_.lidar, lidar_seed, *pool_);
  return f;
}

void SyntheticDataset::write(const std::string& root,
                             const std::function<void(int, int)>& progress) const {
  for (const char* dir :
       {"/lidar/training/image_2", "/lidar/training/velodyne", "/lidar/training/calib",
        "/lidar/training/pose", "/radar/training/velodyne", "/radar/training/calib", "/depth_gt"}) {
    makeDirectories(root + dir);
  }
  const PinholeIntrinsics& k = camera_.intrinsics;
  {
    std::ofstream meta(root + "/scene.json");
    meta.precision(12);
    meta << "{\"generator\": \"make_synthetic_scene\", \"seed\": " << params_.seed
         << ", \"frames\": " << params_.frames << ", \"first_frame\": " << params_.first_frame
         << ", \"scale\": " << params_.scale << ", \"width\": " << camera_.size.width
         << ", \"height\": " << camera_.size.height << ", \"fx\": " << k.fx << ", \"fy\": " << k.fy
         << ", \"cx\": " << k.cx << ", \"cy\": " << k.cy
         << ", \"supersample\": " << params_.effectiveSupersample()
         << ", \"frame_interval_s\": " << params_.path.frame_interval_s
         << ", \"speed\": " << params_.path.speed
         << ", \"radar_range_sigma\": " << params_.radar.range_sigma
         << ", \"radar_azimuth_sigma_deg\": " << params_.radar.azimuth_sigma_deg
         << ", \"radar_elevation_sigma_deg\": " << params_.radar.elevation_sigma_deg
         << ", \"radar_clutter_fraction\": " << params_.radar.clutter_fraction
         << ", \"radar_pass_through\": " << params_.radar.pass_through
         << ", \"radar_ghosts\": " << params_.radar.ghosts
         << ", \"radar_ghost_range_factor_max\": " << params_.radar.ghost_range_factor_max
         << ", \"radar_measures_elevation\": "
         << (params_.radar.measures_elevation ? "true" : "false")
         << ", \"radar_candidates\": " << params_.radar.candidates
         << ", \"lidar_range_sigma\": " << params_.lidar.range_sigma
         << ", \"lidar_beams\": " << params_.lidar.rings << ", \"lidar_elevation_deg\": ["
         << params_.lidar.elevation_min_deg << ", " << params_.lidar.elevation_max_deg << "]"
         << ", \"lidar_azimuth_step_deg\": " << params_.lidar.azimuth_step_deg
         << ", \"camera_height\": " << params_.camera_height
         << ", \"camera_pitch_deg\": " << params_.camera_pitch_deg
         << ", \"extra_vehicles\": " << params_.extra_vehicles
         << ", \"pedestrians\": " << params_.pedestrians
         << ", \"extra_poles\": " << params_.extra_poles
         << ", \"depth_gt\": \"camera z in metres, 0 = sky\"}\n";
    if (!meta) throw InputError(root + "/scene.json: cannot write");
  }
  const std::vector<int> jpeg{cv::IMWRITE_JPEG_QUALITY, params_.jpeg_quality};
  for (int i = 0; i < params_.frames; ++i) {
    const SyntheticFrame f = frame(i);
    const io::VodFrame paths{root, f.number};
    if (!cv::imwrite(paths.image(), f.camera.bgr, jpeg)) {
      throw InputError(paths.image() + ": cannot write image");
    }
    const std::string depth_path = root + "/depth_gt/" + paths.id() + ".npy";
    io::writeNpy(depth_path, f.camera.depth.ptr<float>(),
                 {static_cast<std::size_t>(camera_.size.height),
                  static_cast<std::size_t>(camera_.size.width)});
    std::vector<float> radar;
    radar.reserve(f.radar.size() * 7);
    for (const RadarReturn& r : f.radar) {
      radar.insert(radar.end(), {r.position.x(), r.position.y(), r.position.z(), r.rcs, r.v_r,
                                 r.v_r_compensated, r.time});
    }
    io::writeFloatRecords(paths.points("radar"), radar);
    std::vector<float> lidar;
    lidar.reserve(f.lidar.size() * 4);
    for (const LidarReturn& l : f.lidar) {
      lidar.insert(lidar.end(), {l.position.x(), l.position.y(), l.position.z(), l.intensity});
    }
    io::writeFloatRecords(paths.points("lidar"), lidar);
    io::writeKittiCalib(paths.calib("radar"), k, rig_.radarToCamera());
    io::writeKittiCalib(paths.calib("lidar"), k, rig_.lidarToCamera());
    std::ofstream pose(paths.pose());
    pose << poseJson(f.camera_to_odom);
    if (!pose) throw InputError(paths.pose() + ": cannot write");
    if (progress) progress(i + 1, params_.frames);
  }
}

}  // namespace synthetic
}  // namespace multimodal_nvs
