// io::parsePcd: PCD files through PCL's PCDReader (ascii, binary, binary_compressed), from memory.
// The only file of the package that includes PCL headers (they are slow to compile).
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <streambuf>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/pcd_layout.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

/// PCL's reader prints its own lines to stderr for what this reader reports as an InputError (and
/// warnings such as "no points to read"). Silenced for the process, once, unless the user asked
/// for PCL's messages with PCL_VERBOSITY_LEVEL.
void silencePclConsole() {
  static const bool silenced = [] {
    if (std::getenv("PCL_VERBOSITY_LEVEL") == nullptr)
      pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    return true;
  }();
  (void)silenced;
}

/// Reads a byte range as a stream without copying it (an ascii payload can be hundreds of MB).
class MemoryStreamBuffer : public std::streambuf {
 public:
  MemoryStreamBuffer(const char* begin, const char* end) {
    char* b = const_cast<char*>(begin);  // the get area is only read
    setg(b, b, const_cast<char*>(end));
  }
};

/// PCDReader::readHeader's data_type.
int pclDataType(PcdEncoding encoding) {
  switch (encoding) {
    case PcdEncoding::kAscii:
      return 0;
    case PcdEncoding::kBinary:
      return 1;
    case PcdEncoding::kBinaryCompressed:
      return 2;
  }
  return -1;
}

std::string typeName(const pcl::PCLPointField& f) {
  switch (f.datatype) {
    case pcl::PCLPointField::FLOAT32:
      return "F4";
    case pcl::PCLPointField::FLOAT64:
      return "F8";
    default:
      return "type " + std::to_string(f.datatype) + " (" +
             std::to_string(pcl::getFieldSize(f.datatype)) + " bytes)";
  }
}

/// x, y, z of every point with all three finite, after checking every field against point_step and
/// the data against width * height. PCL marks a missing return of an organised cloud with NaN, so
/// non-finite points are not points here.
std::vector<Eigen::Vector3f> finitePoints(const pcl::PCLPointCloud2& cloud,
                                          const std::string& source) {
  const std::uint64_t count = std::uint64_t(cloud.width) * cloud.height;
  const std::uint64_t step = cloud.point_step;
  if (cloud.data.size() != count * step) {
    throw InputError(source + ": PCD data has " + std::to_string(cloud.data.size()) +
                     " bytes for " + std::to_string(count) + " points of " + std::to_string(step));
  }
  const pcl::PCLPointField* xyz[3] = {nullptr, nullptr, nullptr};
  for (const pcl::PCLPointField& f : cloud.fields) {
    const std::uint64_t size = pcl::getFieldSize(f.datatype);
    if (size == 0 || f.count == 0 || f.offset + size * f.count > step) {
      throw InputError(source + ": PCD field " + f.name + " (" + typeName(f) + " x " +
                       std::to_string(f.count) + " at byte " + std::to_string(f.offset) +
                       ") does not fit in a point of " + std::to_string(step) + " bytes");
    }
    for (int a = 0; a < 3; ++a) {
      if (f.name == std::string(1, "xyz"[a]) && xyz[a] == nullptr) xyz[a] = &f;
    }
  }
  for (int a = 0; a < 3; ++a) {
    if (xyz[a] == nullptr) throw InputError(source + ": PCD has no field " + "xyz"[a]);
    const auto type = xyz[a]->datatype;
    if (type != pcl::PCLPointField::FLOAT32 && type != pcl::PCLPointField::FLOAT64) {
      throw InputError(source + ": PCD field " + xyz[a]->name + " is " + typeName(*xyz[a]) +
                       ", expected F4 or F8");
    }
  }
  std::vector<Eigen::Vector3f> points;
  points.reserve(count);
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint8_t* point = cloud.data.data() + i * step;
    Eigen::Vector3f p;
    for (int a = 0; a < 3; ++a) {
      const std::uint8_t* value = point + xyz[a]->offset;
      if (xyz[a]->datatype == pcl::PCLPointField::FLOAT32) {
        std::memcpy(&p[a], value, sizeof(float));
      } else {
        double v;
        std::memcpy(&v, value, sizeof v);
        p[a] = static_cast<float>(v);  // beyond float's range: inf, dropped below
      }
    }
    if (p.allFinite()) points.push_back(p);
  }
  return points;
}

}  // namespace

std::vector<Eigen::Vector3f> parsePcd(const std::string& bytes, const std::string& source) {
  const PcdLayout layout = checkPcdLayout(bytes, source);
  silencePclConsole();
  pcl::PCDReader reader;
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0;
  unsigned int data_offset = 0;
  // Only the header: PCL would read lines after DATA as header entries too.
  std::istringstream header(bytes.substr(0, layout.payload_offset));
  if (reader.readHeader(header, cloud, origin, orientation, version, data_type, data_offset) < 0) {
    throw InputError(source + ": PCL's PCD reader rejected the header");
  }
  // The allocation bound above holds only if PCL read the header as checkPcdLayout did.
  if (data_type != pclDataType(layout.encoding) || data_offset != layout.payload_offset ||
      cloud.point_step != layout.point_step ||
      std::uint64_t(cloud.width) * cloud.height != layout.points) {
    throw InputError(source + ": PCL's PCD reader reads this header differently");
  }
  if (layout.points > 0) {
    int status = 0;
    if (layout.encoding == PcdEncoding::kAscii) {
      MemoryStreamBuffer buffer(bytes.data() + layout.payload_offset, bytes.data() + bytes.size());
      std::istream body(&buffer);
      status = reader.readBodyASCII(body, cloud, version);
    } else {
      status = reader.readBodyBinary(reinterpret_cast<const unsigned char*>(bytes.data()), cloud,
                                     version, layout.encoding == PcdEncoding::kBinaryCompressed,
                                     data_offset);
    }
    if (status < 0) {
      throw InputError(source + (layout.encoding == PcdEncoding::kBinaryCompressed
                                     ? ": PCD binary_compressed data is corrupt (LZF)"
                                     : ": PCL's PCD reader rejected the data"));
    }
  }
  return finitePoints(cloud, source);
}

}  // namespace io
}  // namespace multimodal_nvs
