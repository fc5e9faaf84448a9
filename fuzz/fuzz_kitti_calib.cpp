// KITTI/VoD calibration text (io::parseKittiCalib) and the accessors the tools call on it.
#include "fuzz_input.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"

namespace io = multimodal_nvs::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  io::KittiCalib calib;
  try {
    calib = io::parseKittiCalib(text, "fuzz");
  } catch (const multimodal_nvs::InputError&) {
    return 0;
  }
  for (const auto& entry : calib.entries)
    MMNVS_FUZZ_CHECK(!entry.first.empty());
  try {
    const auto k = calib.intrinsics();
    MMNVS_FUZZ_CHECK(std::isfinite(k.fx) && k.fx > 0 && std::isfinite(k.fy) && k.fy > 0);
  } catch (const multimodal_nvs::InputError&) {
  }
  try {
    const auto m = calib.sensorToCamera();
    MMNVS_FUZZ_CHECK(m.allFinite());
  } catch (const multimodal_nvs::InputError&) {
  }
  // Whatever key came first, with a count the fuzzer cannot predict.
  if (!calib.entries.empty()) {
    const auto& first = *calib.entries.begin();
    try {
      const auto& numbers = calib.numbers(first.first, size % 16);
      MMNVS_FUZZ_CHECK(numbers.size() >= size % 16);
    } catch (const multimodal_nvs::InputError&) {
    }
  }
  return 0;
}
