#pragma once
// KITTI / View-of-Delft calibration files: P2 and Tr_velo_to_cam.
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
  /// The 3x4 sensor -> camera extrinsic `Tr_velo_to_cam`. Throws InputError.
  SensorToCamera sensorToCamera(const std::string& key = "Tr_velo_to_cam") const;
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
