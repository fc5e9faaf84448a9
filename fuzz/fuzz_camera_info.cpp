// ROS camera_info YAML (io::parseCameraInfoYaml) and the lens model it builds: whatever parses
// must give a valid camera whose projection and ray inversion stay finite or refuse.
#include <cmath>
#include <vector>

#include "fuzz_input.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/camera_info_yaml.hpp"

namespace io = multimodal_nvs::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  io::CameraInfoYaml info;
  try {
    info = io::parseCameraInfoYaml(text, "fuzz");
  } catch (const multimodal_nvs::InputError&) {
    return 0;
  }
  const multimodal_nvs::PinholeIntrinsics& k = info.intrinsics;
  MMNVS_FUZZ_CHECK(info.size.width > 0 && info.size.height > 0);
  MMNVS_FUZZ_CHECK(std::isfinite(k.fx) && k.fx > 0 && std::isfinite(k.fy) && k.fy > 0);
  const int n = k.distortion.coefficientCount();
  MMNVS_FUZZ_CHECK(n == 0 || n == 5 || n == 8);
  MMNVS_FUZZ_CHECK(k.distortion.any() == (n > 0));
  // Corners and centre through the inverse, then forward again.
  std::vector<Eigen::Vector2d> pixels = {
      {0.0, 0.0}, {info.size.width - 1.0, info.size.height - 1.0}, {k.cx, k.cy}};
  k.normalisedRays(pixels);
  for (const Eigen::Vector2d& ray : pixels) {
    double u = 0, v = 0;
    if (ray.allFinite() && k.project(ray.x(), ray.y(), 1.0, &u, &v)) {
      MMNVS_FUZZ_CHECK(!std::isnan(u) && !std::isnan(v));
    }
  }
  return 0;
}
