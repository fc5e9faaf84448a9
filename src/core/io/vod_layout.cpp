#include "multimodal_nvs/core/io/vod_layout.hpp"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

bool hasKittiFolders(const std::string& dir) {
  return directoryExists(dir + "/image_2") || directoryExists(dir + "/velodyne") ||
         directoryExists(dir + "/calib");
}

/// The folder holding image_2/velodyne/calib of a KITTI object root.
std::string kittiBase(const std::string& root) {
  return hasKittiFolders(root) ? root : root + "/training";
}

std::string withImageExtension(const std::string& stem, const char* own, const char* other) {
  const std::string preferred = stem + own;
  if (fileExists(preferred)) return preferred;
  const std::string alternative = stem + other;
  return fileExists(alternative) ? alternative : preferred;
}

}  // namespace

DatasetLayout detectLayout(const std::string& root) {
  return hasKittiFolders(root) || hasKittiFolders(root + "/training") ? DatasetLayout::kKittiObject
                                                                      : DatasetLayout::kVod;
}

const char* toString(DatasetLayout layout) {
  return layout == DatasetLayout::kKittiObject ? "KITTI object" : "View-of-Delft";
}

std::string DatasetFrame::id() const {
  char buf[16];
  std::snprintf(buf, sizeof buf, layout() == DatasetLayout::kKittiObject ? "%06d" : "%05d", frame);
  return buf;
}

std::string DatasetFrame::image() const {
  if (layout() == DatasetLayout::kKittiObject) {
    return withImageExtension(kittiBase(root) + "/image_2/" + id(), ".png", ".jpg");
  }
  return withImageExtension(root + "/lidar/training/image_2/" + id(), ".jpg", ".png");
}

std::string DatasetFrame::pose() const {
  if (layout() == DatasetLayout::kKittiObject) return "";
  return root + "/lidar/training/pose/" + id() + ".json";
}

std::string DatasetFrame::points(const std::string& sensor) const {
  if (layout() == DatasetLayout::kKittiObject) {
    return sensor == "lidar" ? kittiBase(root) + "/velodyne/" + id() + ".bin" : "";
  }
  return root + "/" + sensor + "/training/velodyne/" + id() + ".bin";
}

std::string DatasetFrame::calib(const std::string& sensor) const {
  if (layout() == DatasetLayout::kKittiObject) {
    return sensor == "lidar" ? kittiBase(root) + "/calib/" + id() + ".txt" : "";
  }
  return root + "/" + sensor + "/training/calib/" + id() + ".txt";
}

std::string DatasetFrame::cameraInfo(const std::string& sensor) const {
  const std::string txt = calib(sensor);
  return txt.empty() ? txt : txt.substr(0, txt.size() - 4) + "_camera_info.yaml";
}

int parseFrameNumber(const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < 0 || v > 999999) {
    throw InputError("frame '" + text + "' is not a frame number (0..999999)");
  }
  return static_cast<int>(v);
}

bool fileExists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool directoryExists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace io
}  // namespace multimodal_nvs
