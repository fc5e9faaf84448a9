#include "multimodal_nvs/core/io/vod_layout.hpp"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {

std::string VodFrame::id() const {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%05d", frame);
  return buf;
}
std::string VodFrame::image() const {
  return root + "/lidar/training/image_2/" + id() + ".jpg";
}
std::string VodFrame::pose() const {
  return root + "/lidar/training/pose/" + id() + ".json";
}
std::string VodFrame::points(const std::string& sensor) const {
  return root + "/" + sensor + "/training/velodyne/" + id() + ".bin";
}
std::string VodFrame::calib(const std::string& sensor) const {
  return root + "/" + sensor + "/training/calib/" + id() + ".txt";
}

int parseFrameNumber(const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < 0 || v > 99999) {
    throw InputError("frame '" + text + "' is not a frame number (0..99999)");
  }
  return static_cast<int>(v);
}

bool fileExists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace io
}  // namespace multimodal_nvs
