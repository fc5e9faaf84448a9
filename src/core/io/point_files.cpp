#include "multimodal_nvs/core/io/point_files.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
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

struct PcdField {
  std::string name;
  int size = 4;
  char type = 'F';
  int count = 1;
  std::size_t offset = 0;
};

double readBinaryValue(const char* p, const PcdField& f) {
  if (f.type == 'F' && f.size == 4) {
    float v;
    std::memcpy(&v, p, 4);
    return v;
  }
  double v;
  std::memcpy(&v, p, 8);
  return v;
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

std::vector<Eigen::Vector3f> parsePcd(const std::string& bytes, const std::string& source) {
  std::vector<PcdField> fields;
  std::size_t width = 0, height = 1, points = std::numeric_limits<std::size_t>::max();
  std::string data_kind;
  std::size_t pos = 0;
  while (pos < bytes.size() && data_kind.empty()) {
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::istringstream line(bytes.substr(pos, eol - pos));
    pos = eol + 1;
    std::string key;
    if (!(line >> key) || key[0] == '#') continue;
    std::vector<std::string> values;
    for (std::string v; line >> v;)
      values.push_back(v);
    // strtoull would accept "-1" as 2^64 - 1 and saturate on overflow: digits only, in range.
    auto asCount = [&](const std::string& v, std::size_t max) -> std::size_t {
      char* end = nullptr;
      errno = 0;
      const unsigned long long n = std::strtoull(v.c_str(), &end, 10);
      if (v[0] < '0' || v[0] > '9' || *end != '\0' || errno == ERANGE || n > max)
        throw InputError(source + ": bad PCD " + key + " '" + v + "'");
      return n;
    };
    constexpr std::size_t kAny = std::numeric_limits<std::size_t>::max();
    constexpr std::size_t kInt = std::numeric_limits<int>::max();
    if (key == "FIELDS") {
      fields.resize(values.size());
      for (std::size_t i = 0; i < values.size(); ++i)
        fields[i].name = values[i];
    } else if (key == "SIZE" || key == "TYPE" || key == "COUNT") {
      if (values.size() != fields.size()) {
        throw InputError(source + ": PCD " + key + " has " + std::to_string(values.size()) +
                         " entries for " + std::to_string(fields.size()) + " fields");
      }
      for (std::size_t i = 0; i < values.size(); ++i) {
        if (key == "SIZE") fields[i].size = static_cast<int>(asCount(values[i], kInt));
        if (key == "TYPE") fields[i].type = values[i].empty() ? '?' : values[i][0];
        if (key == "COUNT") fields[i].count = static_cast<int>(asCount(values[i], kInt));
      }
    } else if (key == "WIDTH" && !values.empty()) {
      width = asCount(values[0], kAny);
    } else if (key == "HEIGHT" && !values.empty()) {
      height = asCount(values[0], kAny);
    } else if (key == "POINTS" && !values.empty()) {
      points = asCount(values[0], kAny);
    } else if (key == "DATA") {
      data_kind = values.empty() ? "?" : values[0];
    }
  }
  if (data_kind.empty()) throw InputError(source + ": PCD header has no DATA line");
  if (points == std::numeric_limits<std::size_t>::max()) {
    if (height != 0 && width > std::numeric_limits<std::size_t>::max() / height) {
      throw InputError(source + ": PCD WIDTH * HEIGHT overflows");
    }
    points = width * height;
  }
  int xyz[3] = {-1, -1, -1};
  std::size_t stride = 0;
  // Sums of COUNT: each fits in int, their sum may not.
  std::size_t column = 0;
  std::vector<std::size_t> first_column(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    PcdField& f = fields[i];
    if (f.size <= 0 || f.count <= 0 || f.size > 8)
      throw InputError(source + ": bad PCD field " + f.name);
    f.offset = stride;
    first_column[i] = column;
    stride += std::size_t(f.size) * f.count;
    column += f.count;
    for (int a = 0; a < 3; ++a) {
      if (f.name == std::string(1, "xyz"[a])) {
        if (f.type != 'F' || (f.size != 4 && f.size != 8)) {
          throw InputError(source + ": PCD field " + f.name + " must be F4 or F8");
        }
        xyz[a] = static_cast<int>(i);
      }
    }
  }
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) throw InputError(source + ": PCD lacks x, y or z");
  std::vector<Eigen::Vector3f> out;
  if (data_kind == "ascii") {
    std::istringstream body(bytes.substr(std::min(pos, bytes.size())));
    std::string line;
    while (out.size() < points && std::getline(body, line)) {
      std::istringstream values(line);
      std::vector<double> row;
      for (std::string v; values >> v;)
        row.push_back(std::strtod(v.c_str(), nullptr));
      if (row.empty()) continue;
      if (row.size() < column) {
        throw InputError(source + ": PCD ascii row " + std::to_string(out.size()) + " is short");
      }
      out.emplace_back(row[first_column[xyz[0]]], row[first_column[xyz[1]]],
                       row[first_column[xyz[2]]]);
    }
    if (out.size() < points) throw InputError(source + ": PCD ascii data is truncated");
  } else if (data_kind == "binary") {
    if (stride == 0 || points > (bytes.size() - std::min(pos, bytes.size())) / stride) {
      throw InputError(source + ": PCD binary data is truncated");
    }
    out.resize(points);
    for (std::size_t i = 0; i < points; ++i) {
      const char* rec = bytes.data() + pos + i * stride;
      for (int a = 0; a < 3; ++a) {
        const PcdField& f = fields[xyz[a]];
        out[i][a] = static_cast<float>(readBinaryValue(rec + f.offset, f));
      }
    }
  } else {
    throw InputError(source + ": PCD DATA '" + data_kind + "' is not supported (ascii or binary)");
  }
  return out;
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
