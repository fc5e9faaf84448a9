#pragma once
// View-of-Delft pose files: one JSON object of 4x4 transforms per line.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace multimodal_nvs {
namespace io {

/// The pose key the reference implementation uses (View-of-Delft's dataset layout): the default for
/// camera trajectories, whose relative poses are what matters.
inline const char* defaultVodPoseKey() {
  return "mapToCamera";
}

/// The pose key whose world is the road the vehicle drives on (odometry starts on the ground, z up,
/// and is continuous): the default wherever the absolute height and tilt matter (the ground plane
/// of ground_gp) or a smooth world frame does (/tf in vod_to_bag).
inline const char* odometryVodPoseKey() {
  return "odomToCamera";
}

/// Parses a View-of-Delft pose file: one JSON object per line, keys such as `odomToCamera`,
/// `mapToCamera`, `UTMToCamera`, each a row-major 4x4 camera-to-world matrix (OpenCV camera axes).
/// Returns the matrix under `key`. Throws InputError naming `source` when the text is not JSON, the
/// key is missing (the message lists the keys present), the value is not 16 finite numbers, or the
/// matrix is not a rigid transform (last row 0 0 0 1, orthonormal rotation with determinant +1).
Eigen::Matrix4d parseVodPose(const std::string& text, const std::string& key,
                             const std::string& source);
Eigen::Matrix4d readVodPose(const std::string& path, const std::string& key = defaultVodPoseKey());

/// Every key of a pose file whose value is an array, in file order (for error messages and tools).
std::vector<std::string> vodPoseKeys(const std::string& text, const std::string& source);

}  // namespace io
}  // namespace multimodal_nvs
