// PCD v0.7 point files, ascii and binary (io::parsePcd).
#include "fuzz_input.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace io = multimodal_nvs::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const std::vector<Eigen::Vector3f> points = io::parsePcd(bytes, "fuzz");
    // Every binary point takes at least 12 bytes (x, y, z F4) and every ascii point a line with
    // at least three numbers: more points than that were not read from the input.
    MMNVS_FUZZ_CHECK(points.size() <= size / 4);
  } catch (const multimodal_nvs::InputError&) {
  }
  return 0;
}
