#pragma once
// ROS camera_info YAML (camera_calibration_parsers' format, as written by the ROS camera
// calibrator and read by camera_info_manager): image size, K and the lens distortion.
#include <string>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"

namespace multimodal_nvs {
namespace io {

struct CameraInfoYaml {
  ImageSize size;
  /// K's fx, fy, cx, cy and the distortion of `distortion_model` / `distortion_coefficients`.
  PinholeIntrinsics intrinsics;
};

/// Parses the text of a camera_info YAML: `image_width`, `image_height`, `camera_matrix` (3x3,
/// zero skew) and, optionally, `distortion_model` with `distortion_coefficients` (`rows`, `cols`,
/// `data`). `rectification_matrix` must be identity when present (a rectified stereo camera is not
/// supported). Throws InputError naming `source` and the key; an unsupported distortion model is
/// named in the message.
CameraInfoYaml parseCameraInfoYaml(const std::string& text, const std::string& source);
/// Reads and parses the file; throws InputError with the OS reason when it cannot be opened.
CameraInfoYaml readCameraInfoYaml(const std::string& path);

/// The camera model of a frame: K and the lens distortion of the camera_info YAML when
/// `camera_info_path` is not empty (its size must be `image`: a mismatch throws InputError), else
/// the pinhole of the calibration's P2 (a KITTI text has no distortion).
PinholeIntrinsics frameIntrinsics(const KittiCalib& calib, const std::string& camera_info_path,
                                  const ImageSize& image);

}  // namespace io
}  // namespace multimodal_nvs
