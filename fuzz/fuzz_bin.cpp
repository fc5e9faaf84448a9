// Raw float32 scans (.bin: VoD radar 7 floats, KITTI/VoD LiDAR 4, plain xyz 3): the points reader
// (io::parseFloatRecords) and the all-fields reader (io::parseFloatRecordValues) must agree.
#include <cstring>

#include "fuzz_input.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace io = multimodal_nvs::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  for (const char* format : {"radar", "lidar", "xyz"}) {
    const int n = io::floatsPerRecord(io::parsePointFormat(format));
    std::vector<Eigen::Vector3f> points;
    std::vector<float> values;
    bool points_ok = true, values_ok = true;
    try {
      points = io::parseFloatRecords(bytes, n, "fuzz");
    } catch (const multimodal_nvs::InputError&) {
      points_ok = false;
    }
    try {
      values = io::parseFloatRecordValues(bytes, n, "fuzz");
    } catch (const multimodal_nvs::InputError&) {
      values_ok = false;
    }
    MMNVS_FUZZ_CHECK(points_ok == values_ok);
    MMNVS_FUZZ_CHECK(points_ok == (size % (4 * n) == 0));
    if (!points_ok) continue;
    MMNVS_FUZZ_CHECK(values.size() == points.size() * n);
    // Bitwise, so that NaN payloads count as equal.
    for (std::size_t i = 0; i < points.size(); ++i) {
      MMNVS_FUZZ_CHECK(std::memcmp(points[i].data(), &values[i * n], 3 * sizeof(float)) == 0);
    }
  }
  return 0;
}
