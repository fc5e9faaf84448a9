// PCD v0.7 point files, ascii, binary and binary_compressed: io::parsePcd, i.e. io::checkPcdLayout
// and then PCL's PCDReader (readHeader, readBodyASCII, readBodyBinary with its LZF decoder) on what
// the check accepted. PCL itself is not instrumented, but its copies into and out of the cloud go
// through memcpy, which ASan intercepts and bounds-checks, and its allocations through ASan's
// allocator, where libFuzzer's malloc limit (= -rss_limit_mb) reports one the input cannot justify.
#include <cmath>

#include "fuzz_input.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace io = multimodal_nvs::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const std::vector<Eigen::Vector3f> points = io::parsePcd(bytes, "fuzz");
    // A point takes at least 12 bytes (x, y, z F4) of data, and LZF unpacks at most 88 bytes per
    // input byte (ascii and binary: at most 1): more points than that were not read from the input.
    MMNVS_FUZZ_CHECK(points.size() * 12 <= 88 * size);
    for (const Eigen::Vector3f& p : points)
      MMNVS_FUZZ_CHECK(p.allFinite());
  } catch (const multimodal_nvs::InputError&) {
  }
  return 0;
}
