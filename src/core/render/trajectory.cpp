#include "multimodal_nvs/core/render/trajectory.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace {

Eigen::Matrix4d rigidInverse(const Eigen::Matrix4d& m) {
  Eigen::Matrix4d inv = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d rt = m.topLeftCorner<3, 3>().transpose();
  inv.topLeftCorner<3, 3>() = rt;
  inv.topRightCorner<3, 1>() = -rt * m.topRightCorner<3, 1>();
  return inv;
}

void requireFrameCount(int num_frames) {
  if (num_frames < 1)
    throw InputError("number of frames must be >= 1 (got " + std::to_string(num_frames) + ")");
}

void requireSize(ImageSize size) {
  if (size.height <= 0 || size.width <= 0) throw InputError("render size must be positive");
}

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

std::vector<Eigen::Matrix4d> relativeWorldToCamera(
    const std::vector<Eigen::Matrix4d>& camera_to_world) {
  if (camera_to_world.empty()) throw InputError("trajectory needs at least one pose");
  std::vector<Eigen::Matrix4d> out;
  out.reserve(camera_to_world.size());
  for (const Eigen::Matrix4d& t : camera_to_world) {
    out.push_back(rigidInverse(t) * camera_to_world.front());
  }
  return out;
}

Eigen::Matrix4d interpolateCameraPose(const Eigen::Matrix4d& a_camera_to_world,
                                      const Eigen::Matrix4d& b_camera_to_world, double t) {
  const Eigen::Quaterniond qa(Eigen::Matrix3d(a_camera_to_world.topLeftCorner<3, 3>()));
  const Eigen::Quaterniond qb(Eigen::Matrix3d(b_camera_to_world.topLeftCorner<3, 3>()));
  Eigen::Matrix4d out = Eigen::Matrix4d::Identity();
  // Exact endpoints: slerp(0) and slerp(1) round-trip through a quaternion, which costs ~1e-16.
  if (t <= 0.0) return a_camera_to_world;
  if (t >= 1.0) return b_camera_to_world;
  out.topLeftCorner<3, 3>() = qa.normalized().slerp(t, qb.normalized()).toRotationMatrix();
  out.topRightCorner<3, 1>() = (1.0 - t) * a_camera_to_world.topRightCorner<3, 1>() +
                               t * b_camera_to_world.topRightCorner<3, 1>();
  return out;
}

std::vector<int> recordedFrameIndices(int num_poses, int num_frames) {
  requireFrameCount(num_frames);
  if (num_poses < 1) throw InputError("trajectory needs at least one pose");
  if (num_poses > num_frames) {
    throw InputError("cannot place " + std::to_string(num_poses) + " recorded poses on " +
                     std::to_string(num_frames) + " frames: use --num-frames >= the pose count");
  }
  std::vector<int> indices(static_cast<std::size_t>(num_poses), 0);
  for (int j = 1; j < num_poses; ++j) {
    indices[static_cast<std::size_t>(j)] =
        static_cast<int>(std::lround(static_cast<double>(j) * (num_frames - 1) / (num_poses - 1)));
  }
  return indices;
}

Trajectory recordedTrajectory(const std::vector<Eigen::Matrix4d>& camera_to_world, int num_frames,
                              const PinholeIntrinsics& intrinsics, ImageSize size) {
  requireSize(size);
  intrinsics.validate("target intrinsics");
  const std::vector<int> keys =
      recordedFrameIndices(static_cast<int>(camera_to_world.size()), num_frames);
  // Interpolate the camera poses in the reference frame (inv(T_0) T_i), then invert per frame.
  std::vector<Eigen::Matrix4d> relative_c2w;
  for (const Eigen::Matrix4d& w2c : relativeWorldToCamera(camera_to_world)) {
    relative_c2w.push_back(rigidInverse(w2c));
  }
  Trajectory traj;
  traj.size = size;
  traj.recorded_frames = keys;
  traj.cameras.resize(static_cast<std::size_t>(num_frames));
  for (std::size_t j = 0; j < keys.size(); ++j) {
    const int begin = keys[j];
    const int end = j + 1 < keys.size() ? keys[j + 1] : begin;
    for (int i = begin; i <= end; ++i) {
      const double t = end > begin ? static_cast<double>(i - begin) / (end - begin) : 0.0;
      const Eigen::Matrix4d c2w =
          j + 1 < keys.size() ? interpolateCameraPose(relative_c2w[j], relative_c2w[j + 1], t)
                              : relative_c2w[j];
      TargetCamera& cam = traj.cameras[static_cast<std::size_t>(i)];
      cam.world_to_camera = rigidInverse(c2w);
      cam.intrinsics = intrinsics;
    }
  }
  // Recorded poses are set from the exact relative matrices, not from a round trip through
  // inversion twice, so frame 0 is the identity to the last bit.
  const std::vector<Eigen::Matrix4d> w2c = relativeWorldToCamera(camera_to_world);
  for (std::size_t j = 0; j < keys.size(); ++j) {
    traj.cameras[static_cast<std::size_t>(keys[j])].world_to_camera = w2c[j];
  }
  traj.cameras.front().world_to_camera = Eigen::Matrix4d::Identity();
  return traj;
}

namespace {

struct PresetName {
  TrajectoryPreset preset;
  const char* name;
};

constexpr PresetName kPresetNames[] = {
    {TrajectoryPreset::kForward, "forward"},
    {TrajectoryPreset::kBackward, "backward"},
    {TrajectoryPreset::kLeft, "left"},
    {TrajectoryPreset::kRight, "right"},
    {TrajectoryPreset::kUp, "up"},
    {TrajectoryPreset::kDown, "down"},
    {TrajectoryPreset::kOrbitLeft, "orbit_left"},
    {TrajectoryPreset::kOrbitRight, "orbit_right"},
    {TrajectoryPreset::kZoomIn, "zoom_in"},
    {TrajectoryPreset::kZoomOut, "zoom_out"},
};

}  // namespace

TrajectoryPreset parseTrajectoryPreset(const std::string& name) {
  std::string all;
  for (const PresetName& p : kPresetNames) {
    if (name == p.name) return p.preset;
    all += (all.empty() ? "" : ", ") + std::string(p.name);
  }
  throw InputError("unknown trajectory preset '" + name + "' (valid: " + all + ")");
}

std::string toString(TrajectoryPreset preset) {
  for (const PresetName& p : kPresetNames) {
    if (p.preset == preset) return p.name;
  }
  return "unknown";
}

std::string magnitudeUnit(TrajectoryPreset preset) {
  switch (preset) {
    case TrajectoryPreset::kOrbitLeft:
    case TrajectoryPreset::kOrbitRight:
    case TrajectoryPreset::kZoomIn:
    case TrajectoryPreset::kZoomOut:
      return "deg";
    default:
      return "m";
  }
}

Trajectory presetTrajectory(TrajectoryPreset preset, double magnitude, int num_frames,
                            const PinholeIntrinsics& intrinsics, ImageSize size,
                            double orbit_centre_depth) {
  requireFrameCount(num_frames);
  requireSize(size);
  intrinsics.validate("target intrinsics");
  if (!std::isfinite(magnitude) || magnitude < 0.0) {
    throw InputError("preset magnitude must be finite and >= 0 (got " + std::to_string(magnitude) +
                     "); the preset name gives the direction");
  }
  const bool orbit =
      preset == TrajectoryPreset::kOrbitLeft || preset == TrajectoryPreset::kOrbitRight;
  if (orbit && !(orbit_centre_depth > 0.0 && std::isfinite(orbit_centre_depth))) {
    throw InputError("orbit centre depth must be positive (median kept depth was " +
                     std::to_string(orbit_centre_depth) + ")");
  }
  // Horizontal field of view of the reference, for the zoom presets.
  const double fov0 = 2.0 * std::atan(0.5 * size.width / intrinsics.fx);
  if (preset == TrajectoryPreset::kZoomIn || preset == TrajectoryPreset::kZoomOut) {
    const double sign = preset == TrajectoryPreset::kZoomIn ? -1.0 : 1.0;
    const double fov1 = fov0 + sign * magnitude * kDegToRad;
    if (!(fov1 > 0.0 && fov1 < M_PI)) {
      throw InputError("zoom by " + std::to_string(magnitude) +
                       " deg leaves the horizontal field " + "of view (" +
                       std::to_string(fov0 / kDegToRad) + " deg) outside (0, 180)");
    }
  }

  Trajectory traj;
  traj.size = size;
  traj.cameras.resize(static_cast<std::size_t>(num_frames));
  for (int i = 0; i < num_frames; ++i) {
    const double t = num_frames > 1 ? static_cast<double>(i) / (num_frames - 1) : 0.0;
    const double s = t * magnitude;
    Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
    PinholeIntrinsics k = intrinsics;
    switch (preset) {
      case TrajectoryPreset::kForward:
        c2w(2, 3) = s;
        break;
      case TrajectoryPreset::kBackward:
        c2w(2, 3) = -s;
        break;
      case TrajectoryPreset::kLeft:
        c2w(0, 3) = -s;
        break;
      case TrajectoryPreset::kRight:
        c2w(0, 3) = s;
        break;
      case TrajectoryPreset::kUp:
        c2w(1, 3) = -s;
        break;  // y points down
      case TrajectoryPreset::kDown:
        c2w(1, 3) = s;
        break;
      case TrajectoryPreset::kOrbitLeft:
      case TrajectoryPreset::kOrbitRight: {
        // A positive turn about +y (down) swings the camera centre to -x (left) while its optical
        // axis keeps passing through the centre point.
        const double angle = (preset == TrajectoryPreset::kOrbitLeft ? 1.0 : -1.0) * s * kDegToRad;
        const Eigen::Matrix3d r =
            Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
        const Eigen::Vector3d centre(0.0, 0.0, orbit_centre_depth);
        c2w.topLeftCorner<3, 3>() = r;
        c2w.topRightCorner<3, 1>() = centre + r * (-centre);
        break;
      }
      case TrajectoryPreset::kZoomIn:
      case TrajectoryPreset::kZoomOut: {
        const double sign = preset == TrajectoryPreset::kZoomIn ? -1.0 : 1.0;
        const double fov = fov0 + sign * s * kDegToRad;
        const double scale = std::tan(0.5 * fov0) / std::tan(0.5 * fov);
        k.fx *= scale;
        k.fy *= scale;
        // Zoom about the principal point: cx, cy stay.
        break;
      }
    }
    TargetCamera& cam = traj.cameras[static_cast<std::size_t>(i)];
    cam.world_to_camera = rigidInverse(c2w);
    cam.intrinsics = k;
  }
  return traj;
}

}  // namespace multimodal_nvs
