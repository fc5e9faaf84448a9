#pragma once
// The file paths of one frame in the View-of-Delft layout.
#include <string>

namespace multimodal_nvs {
namespace io {

/// Paths of one frame in the View-of-Delft layout (View-of-Delft's dataset layout):
/// ROOT/{lidar,radar}/training/{image_2,velodyne,calib,pose}/NNNNN.{jpg,bin,txt,json}.
struct VodFrame {
  std::string root;
  int frame = 0;

  std::string id() const;  ///< five digits, zero padded
  std::string image() const;
  std::string pose() const;
  std::string points(const std::string& sensor) const;  ///< sensor: radar | lidar
  std::string calib(const std::string& sensor) const;
};

/// Parses a frame number with or without leading zeros ("08350", "8350"); throws InputError.
int parseFrameNumber(const std::string& text);

bool fileExists(const std::string& path);

}  // namespace io
}  // namespace multimodal_nvs
