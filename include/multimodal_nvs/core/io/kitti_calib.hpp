#pragma once
// KITTI / View-of-Delft calibration files: P2, R0_rect and Tr_velo_to_cam.
#include <map>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"

namespace multimodal_nvs {
namespace io {

/// A KITTI/VoD calibration text: `KEY: n1 n2 ...` per line (keys with no numbers are kept empty).
struct KittiCalib {
  std::string source;
  std::map<std::string, std::vector<double>> entries;

  /// fx, fy, cx, cy from `P2` ([0,0], [1,1], [0,2], [1,2] of the 3x4 projection). Throws
  /// InputError.
  PinholeIntrinsics intrinsics(const std::string& key = "P2") const;
  /// The 3x4 sensor -> camera extrinsic into the camera of `projection`, as KITTI's object devkit
  /// projects (x_image = P2 · R0_rect · Tr_velo_to_cam · x): `Tr_velo_to_cam` (reference camera),
  /// then `R0_rect` when present (the rectifying rotation, ~0.6 degrees on KITTI), then the
  /// projection's own translation K⁻¹·P[:, 3] (camera 2 sits ~6 cm left of camera 0 on KITTI).
  /// VoD-style files (identity R0_rect, zero fourth column) give `Tr_velo_to_cam` unchanged.
  /// Throws InputError.
  SensorToCamera sensorToCamera(const std::string& projection = "P2") const;
  /// The raw 3x4 matrix of `key` (e.g. `Tr_velo_to_cam`). Throws InputError.
  SensorToCamera matrix3x4(const std::string& key) const;
  /// The first `count` numbers of `key`; throws InputError when missing or shorter.
  const std::vector<double>& numbers(const std::string& key, std::size_t count) const;
};

KittiCalib parseKittiCalib(const std::string& text, const std::string& source);
KittiCalib readKittiCalib(const std::string& path);
/// Writes P2 and Tr_velo_to_cam (plus P0..P3, R0_rect like VoD) so that readers of either find
/// them.
void writeKittiCalib(const std::string& path, const PinholeIntrinsics& k,
                     const SensorToCamera& sensor_to_camera);

}  // namespace io
}  // namespace multimodal_nvs
