#include "multimodal_nvs/core/io/pcd_layout.hpp"

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

// The v0.7 header entries in the order the format requires them.
constexpr std::array<const char*, 10> kEntries = {
    "VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
enum Entry { kVersion, kFields, kSize, kType, kCount, kWidth, kHeight, kViewpoint, kPoints, kData };

// PCL splits header and ascii lines at these characters (pcl::split).
constexpr const char* kSeparators = " \t\r";

// PCL indexes point data with int (pcl::index_t) and keeps point_step and sizes in int / unsigned.
constexpr std::uint64_t kMaxIntBytes = std::numeric_limits<int>::max();
constexpr std::uint64_t kMaxU32 = std::numeric_limits<std::uint32_t>::max();

// LZF's longest back reference writes 264 bytes from 3 input bytes; a literal run never expands.
constexpr std::uint64_t kLzfMaxExpansion = 88;

std::vector<std::string> tokensOf(const std::string& line) {
  std::vector<std::string> out;
  for (std::size_t start = line.find_first_not_of(kSeparators); start != std::string::npos;) {
    const std::size_t end = line.find_first_of(kSeparators, start);
    out.push_back(line.substr(start, end == std::string::npos ? std::string::npos : end - start));
    start = end == std::string::npos ? end : line.find_first_not_of(kSeparators, end);
  }
  return out;
}

/// Numbers on an ascii row, counted as PCL's split counts them, without allocating.
std::uint64_t tokenCount(const char* begin, const char* end) {
  std::uint64_t n = 0;
  bool in_token = false;
  for (const char* c = begin; c != end; ++c) {
    const bool separator = *c == ' ' || *c == '\t' || *c == '\r';
    if (!separator && !in_token) ++n;
    in_token = !separator;
  }
  return n;
}

class HeaderReader {
 public:
  explicit HeaderReader(const std::string& source) : source_(source) {}

  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(source_ + ": PCD header line " + std::to_string(line_) + ": " + why);
  }

  /// Digits only (PCL's stream extraction would take "-1" for 2^32 - 1), at most `max`.
  std::uint64_t number(const std::string& entry, const std::string& v, std::uint64_t max) const {
    char* end = nullptr;
    errno = 0;
    const unsigned long long n = std::strtoull(v.c_str(), &end, 10);
    // The whole token: PCL's stream extraction stops at a NUL byte where this would too.
    if (v[0] < '0' || v[0] > '9' || end != v.c_str() + v.size() || errno == ERANGE || n > max) {
      fail("bad " + entry + " '" + v + "' (expected a whole number up to " + std::to_string(max) +
           ")");
    }
    return n;
  }

  void expectPerField(const std::string& entry, const std::vector<std::string>& values) const {
    if (values.size() != names_.size()) {
      fail(entry + " has " + std::to_string(values.size()) + " entries for " +
           std::to_string(names_.size()) + " fields");
    }
  }

  void expectOne(const std::string& entry, const std::vector<std::string>& values) const {
    if (values.size() != 1) fail(entry + " needs one value, has " + std::to_string(values.size()));
  }

  void read(Entry entry, const std::vector<std::string>& values, PcdLayout& layout) {
    const std::string name = kEntries[entry];
    switch (entry) {
      case kVersion:
        break;
      case kFields:
        if (values.empty()) fail("FIELDS names no field");
        names_ = values;
        sizes_.assign(names_.size(), 0);
        counts_.assign(names_.size(), 1);
        break;
      case kSize:
        expectPerField(name, values);
        for (std::size_t i = 0; i < values.size(); ++i) {
          sizes_[i] = number(name, values[i], 8);
          if (sizes_[i] != 1 && sizes_[i] != 2 && sizes_[i] != 4 && sizes_[i] != 8)
            fail("SIZE of field " + names_[i] + " is " + values[i] + " (expected 1, 2, 4 or 8)");
        }
        break;
      case kType:
        expectPerField(name, values);
        for (std::size_t i = 0; i < values.size(); ++i) {
          const std::string& t = values[i];
          const bool known = t == "I" || t == "U" || (t == "F" && sizes_[i] >= 4);
          if (!known) {
            fail("field " + names_[i] + " has TYPE '" + t + "' with SIZE " +
                 std::to_string(sizes_[i]) + " (expected I or U, or F with SIZE 4 or 8)");
          }
        }
        break;
      case kCount:
        expectPerField(name, values);
        for (std::size_t i = 0; i < values.size(); ++i) {
          counts_[i] = number(name, values[i], kMaxIntBytes);
          if (counts_[i] == 0) fail("COUNT of field " + names_[i] + " is 0");
        }
        break;
      case kWidth:
      case kHeight:
        expectOne(name, values);
        (entry == kWidth ? width_ : height_) = number(name, values[0], kMaxU32);
        break;
      case kViewpoint:
        if (values.size() != 7) fail("VIEWPOINT needs 7 numbers (tx ty tz qw qx qy qz)");
        for (const std::string& v : values) {
          char* end = nullptr;
          std::strtod(v.c_str(), &end);
          if (end == v.c_str() || end != v.c_str() + v.size())
            fail("VIEWPOINT value '" + v + "' is not a number");
        }
        break;
      case kPoints:
        expectOne(name, values);
        layout.points = number(name, values[0], kMaxU32);
        break;
      case kData:
        expectOne(name, values);
        if (values[0] == "ascii") {
          layout.encoding = PcdEncoding::kAscii;
        } else if (values[0] == "binary") {
          layout.encoding = PcdEncoding::kBinary;
        } else if (values[0] == "binary_compressed") {
          layout.encoding = PcdEncoding::kBinaryCompressed;
        } else {
          fail("DATA '" + values[0] + "' (expected ascii, binary or binary_compressed)");
        }
        break;
    }
  }

  /// Reads up to and including the DATA line.
  PcdLayout readHeader(const std::string& bytes) {
    PcdLayout layout;
    int previous = -1;
    std::size_t pos = 0;
    while (previous != kData) {
      ++line_;
      const std::size_t eol = bytes.find('\n', pos);
      if (eol == std::string::npos) fail("the header ends before a DATA line and its newline");
      const std::string line = bytes.substr(pos, eol - pos);
      pos = eol + 1;
      if (line.empty()) continue;  // PCL skips empty lines, and only those.
      const std::vector<std::string> tokens = tokensOf(line);
      if (!tokens.empty() && tokens[0][0] == '#') continue;
      int entry = -1;
      for (std::size_t e = 0; e < kEntries.size() && !tokens.empty(); ++e) {
        if (tokens[0] == kEntries[e]) entry = static_cast<int>(e);
      }
      // PCL stops reading the header at a line it does not know (and reads the data from byte 0),
      // reads an entry given twice twice, and sizes POINTS by the SIZE and COUNT read before it.
      if (entry < 0) fail("'" + line.substr(0, 40) + "' is not a PCD v0.7 header entry");
      if (entry <= previous) {
        fail(std::string(kEntries[entry]) + " comes after " + kEntries[previous] +
             " (v0.7 order: VERSION FIELDS SIZE TYPE COUNT WIDTH HEIGHT VIEWPOINT POINTS DATA)");
      }
      for (int missing : {kFields, kSize, kType}) {
        if (entry > missing && previous < missing) fail(std::string("no ") + kEntries[missing]);
      }
      if (entry == kData && previous != kPoints) fail("no POINTS before DATA");
      if (entry == kPoints && (!width_seen() || !height_seen())) fail("no WIDTH or HEIGHT");
      read(static_cast<Entry>(entry), std::vector<std::string>(tokens.begin() + 1, tokens.end()),
           layout);
      previous = entry;
    }
    layout.payload_offset = pos;
    if (width_ * height_ != layout.points) {
      throw InputError(source_ + ": PCD WIDTH x HEIGHT (" + std::to_string(width_) + " x " +
                       std::to_string(height_) + ") is not POINTS (" +
                       std::to_string(layout.points) + ")");
    }
    for (std::size_t i = 0; i < names_.size(); ++i) {
      layout.point_step += sizes_[i] * counts_[i];
      layout.values_per_point += counts_[i];
      if (layout.point_step > kMaxIntBytes) throw InputError(source_ + ": PCD point is too large");
    }
    if (layout.points * layout.point_step > kMaxIntBytes) {
      throw InputError(source_ + ": PCD point data of " + std::to_string(layout.points) + " x " +
                       std::to_string(layout.point_step) +
                       " bytes is over 2 GiB (PCL's reader indexes it with int)");
    }
    return layout;
  }

  bool hasPaddingField() const {
    for (const std::string& n : names_) {
      if (n == "_") return true;
    }
    return false;
  }

 private:
  bool width_seen() const { return width_ != kUnset; }
  bool height_seen() const { return height_ != kUnset; }

  static constexpr std::uint64_t kUnset = std::numeric_limits<std::uint64_t>::max();
  const std::string& source_;
  int line_ = 0;
  std::vector<std::string> names_;
  std::vector<std::uint64_t> sizes_, counts_;
  std::uint64_t width_ = kUnset, height_ = kUnset;
};

void checkBinary(const std::string& bytes, const PcdLayout& layout, const std::string& source) {
  const std::uint64_t present = bytes.size() - layout.payload_offset;
  const std::uint64_t needed = layout.points * layout.point_step;
  if (present < needed) {
    throw InputError(source + ": PCD binary data is truncated: " + std::to_string(layout.points) +
                     " points x " + std::to_string(layout.point_step) + " bytes need " +
                     std::to_string(needed) + " bytes, the file has " + std::to_string(present) +
                     " after DATA");
  }
}

// PCL reads two little-endian size words, then decompresses with the stored sizes; it resizes the
// cloud to the stored uncompressed size when that disagrees with the header.
void checkCompressed(const std::string& bytes, const PcdLayout& layout, const std::string& source,
                     bool padding_field) {
  const std::string prefix = source + ": PCD binary_compressed data ";
  // PCL unpacks compressed fields by the sizes of the fields not named "_" but places them by
  // offsets that count them: the bytes land outside the point.
  if (padding_field) throw InputError(prefix + "with a padding field '_' is not supported");
  const std::uint64_t present = bytes.size() - layout.payload_offset;
  if (present < 8) throw InputError(prefix + "is truncated: no size words");
  std::uint32_t compressed = 0, uncompressed = 0;
  std::memcpy(&compressed, bytes.data() + layout.payload_offset, 4);
  std::memcpy(&uncompressed, bytes.data() + layout.payload_offset + 4, 4);
  const std::uint64_t expected = layout.points * layout.point_step;
  if (uncompressed != expected) {
    throw InputError(prefix + "is corrupt: it unpacks to " + std::to_string(uncompressed) +
                     " bytes, the header needs " + std::to_string(expected));
  }
  if (compressed == 0 || compressed > present - 8) {
    throw InputError(prefix + "is corrupt or truncated: " + std::to_string(compressed) +
                     " compressed bytes announced, " + std::to_string(present - 8) + " present");
  }
  if (expected > kLzfMaxExpansion * compressed) {
    throw InputError(prefix + "is corrupt: " + std::to_string(compressed) +
                     " LZF bytes cannot unpack to " + std::to_string(expected));
  }
}

// PCL counts a row with the wrong number of values as read and leaves its point zero.
void checkAsciiRows(const std::string& bytes, const PcdLayout& layout, const std::string& source) {
  std::uint64_t rows = 0;
  std::size_t pos = layout.payload_offset;
  while (rows < layout.points && pos < bytes.size()) {
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    const std::size_t begin = pos;
    pos = eol + 1;
    if (eol == begin) continue;  // an empty line, skipped as PCL skips it
    const std::uint64_t values = tokenCount(bytes.data() + begin, bytes.data() + eol);
    if (values != layout.values_per_point) {
      throw InputError(source + ": PCD ascii row " + std::to_string(rows + 1) + " has " +
                       std::to_string(values) + " values, the header needs " +
                       std::to_string(layout.values_per_point));
    }
    ++rows;
  }
  if (rows < layout.points) {
    throw InputError(source + ": PCD ascii data is truncated: " + std::to_string(rows) + " of " +
                     std::to_string(layout.points) + " rows");
  }
}

}  // namespace

PcdLayout checkPcdLayout(const std::string& bytes, const std::string& source) {
  HeaderReader reader(source);
  const PcdLayout layout = reader.readHeader(bytes);
  if (layout.points == 0) return layout;
  switch (layout.encoding) {
    case PcdEncoding::kAscii:
      checkAsciiRows(bytes, layout, source);
      break;
    case PcdEncoding::kBinary:
      checkBinary(bytes, layout, source);
      break;
    case PcdEncoding::kBinaryCompressed:
      checkCompressed(bytes, layout, source, reader.hasPaddingField());
      break;
  }
  return layout;
}

}  // namespace io
}  // namespace multimodal_nvs
