#pragma once
// The file paths of one frame of a dataset folder: the View-of-Delft layout or KITTI's object
// layout, told apart by the folder itself.
#include <string>

namespace multimodal_nvs {
namespace io {

enum class DatasetLayout {
  /// View-of-Delft: ROOT/{lidar,radar}/training/{image_2,velodyne,calib,pose}/NNNNN.{jpg,bin,
  /// txt,json} (five-digit names; make_synthetic_scene writes it too).
  kVod,
  /// KITTI object detection as downloaded: ROOT/{image_2,velodyne,calib}/NNNNNN.{png,bin,txt}
  /// (six-digit names, LiDAR only, no poses). ROOT may also be the folder holding `training/`.
  kKittiObject,
};

/// The layout of `root`: KITTI object when it (or its `training/`) has an `image_2`, `velodyne`
/// or `calib` folder of its own, View-of-Delft otherwise.
DatasetLayout detectLayout(const std::string& root);
const char* toString(DatasetLayout layout);

/// Paths of one frame; the layout is detected from `root` on each call (a few stat calls).
struct DatasetFrame {
  std::string root;
  int frame = 0;

  DatasetLayout layout() const { return detectLayout(root); }
  std::string id() const;  ///< zero padded: five digits (VoD), six (KITTI)
  /// The camera image: the layout's own extension (.jpg VoD, .png KITTI), or the other one when
  /// only that exists.
  std::string image() const;
  /// The pose JSON; empty for KITTI object (it has none: every model runs without a pose).
  std::string pose() const;
  /// sensor: radar | lidar. Empty when the layout has no such sensor (KITTI object: no radar).
  std::string points(const std::string& sensor) const;
  std::string calib(const std::string& sensor) const;
  /// The ROS camera_info YAML beside the calibration (calib/NNNNN_camera_info.yaml), which carries
  /// the lens distortion a KITTI text cannot; tools use it when it exists.
  std::string cameraInfo(const std::string& sensor) const;
};
/// The historical name (the tools were written for View-of-Delft first).
using VodFrame = DatasetFrame;

/// Parses a frame number with or without leading zeros ("08350", "8350", "000100"); throws
/// InputError.
int parseFrameNumber(const std::string& text);

bool fileExists(const std::string& path);
bool directoryExists(const std::string& path);

}  // namespace io
}  // namespace multimodal_nvs
