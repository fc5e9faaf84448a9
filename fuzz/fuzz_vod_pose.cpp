// View-of-Delft pose JSON (io::parseVodPose, io::vodPoseKeys).
#include <cmath>

#include "fuzz_input.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"

namespace io = multimodal_nvs::io;

namespace {

void checkPose(const std::string& text, const std::string& key) {
  try {
    const Eigen::Matrix4d m = io::parseVodPose(text, key, "fuzz");
    // Accepted poses are finite rigid transforms.
    MMNVS_FUZZ_CHECK(m.allFinite());
    MMNVS_FUZZ_CHECK(m(3, 0) == 0.0 || std::abs(m(3, 0)) <= 1e-9);
    MMNVS_FUZZ_CHECK(std::abs(m(3, 3) - 1.0) <= 1e-9);
  } catch (const multimodal_nvs::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> keys;
  try {
    keys = io::vodPoseKeys(text, "fuzz");
  } catch (const multimodal_nvs::InputError&) {
  }
  checkPose(text, io::defaultVodPoseKey());
  // Keys the file has reach the matrix checks even when the fuzzer has not found "mapToCamera".
  for (std::size_t i = 0; i < keys.size() && i < 4; ++i)
    checkPose(text, keys[i]);
  return 0;
}
