#include "multimodal_nvs/core/io/point_files.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open point file (" + std::strerror(errno) + ")");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

PointFormat parsePointFormat(const std::string& name) {
  if (name == "radar" || name == "vod7") return PointFormat::kVodRadar;
  if (name == "lidar" || name == "xyzi") return PointFormat::kXyzi;
  if (name == "xyz" || name == "xyz3") return PointFormat::kXyz;
  if (name == "pcd") return PointFormat::kPcd;
  throw InputError("unknown point format '" + name + "' (expected radar, lidar, xyz or pcd)");
}

int floatsPerRecord(PointFormat format) {
  switch (format) {
    case PointFormat::kVodRadar:
      return 7;
    case PointFormat::kXyzi:
      return 4;
    case PointFormat::kXyz:
      return 3;
    case PointFormat::kPcd:
      return 0;
  }
  return 0;
}

namespace {

/// Bytes per record; throws InputError unless `bytes` holds whole records.
std::size_t checkRecordSize(const std::string& bytes, int floats_per_record,
                            const std::string& source) {
  const std::size_t record = sizeof(float) * floats_per_record;
  if (bytes.size() % record != 0) {
    throw InputError(source + ": size " + std::to_string(bytes.size()) +
                     " bytes is not a multiple of the " + std::to_string(record) +
                     "-byte record (" + std::to_string(floats_per_record) + " float32)");
  }
  return record;
}

}  // namespace

std::vector<Eigen::Vector3f> parseFloatRecords(const std::string& bytes, int floats_per_record,
                                               const std::string& source) {
  const std::size_t record = checkRecordSize(bytes, floats_per_record, source);
  const std::size_t count = bytes.size() / record;
  std::vector<Eigen::Vector3f> points(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::memcpy(points[i].data(), bytes.data() + i * record, 3 * sizeof(float));
  }
  return points;
}

std::vector<Eigen::Vector3f> readPoints(const std::string& path, PointFormat format) {
  const std::string bytes = readAll(path);
  if (format == PointFormat::kPcd) return parsePcd(bytes, path);
  return parseFloatRecords(bytes, floatsPerRecord(format), path);
}

std::vector<float> parseFloatRecordValues(const std::string& bytes, int floats_per_record,
                                          const std::string& source) {
  checkRecordSize(bytes, floats_per_record, source);
  std::vector<float> values(bytes.size() / sizeof(float));
  // An empty file leaves values.data() null, which memcpy must not get even for 0 bytes.
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

std::vector<float> readFloatRecords(const std::string& path, int floats_per_record) {
  return parseFloatRecordValues(readAll(path), floats_per_record, path);
}

void writeFloatRecords(const std::string& path, const std::vector<float>& values) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path + ": cannot open for writing");
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(float)));
  if (!out) throw InputError(path + ": write failed");
}

}  // namespace io
}  // namespace multimodal_nvs
