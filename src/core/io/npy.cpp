#include "multimodal_nvs/core/io/npy.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

std::size_t itemSize(const std::string& dtype) {
  if (dtype == "<f4" || dtype == "<i4") return 4;
  if (dtype == "<f8" || dtype == "<i8") return 8;
  if (dtype == "|u1" || dtype == "|b1" || dtype == "<u1") return 1;
  return 0;
}

// Extracts the quoted value or the parenthesised tuple after 'key': in a header dict.
std::string dictValue(const std::string& header, const std::string& key, const std::string& src) {
  const std::string quoted = "'" + key + "'";
  const std::size_t k = header.find(quoted);
  if (k == std::string::npos) throw InputError(src + ": .npy header has no '" + key + "'");
  std::size_t p = header.find(':', k + quoted.size());
  if (p == std::string::npos) throw InputError(src + ": malformed .npy header");
  ++p;
  while (p < header.size() && header[p] == ' ')
    ++p;
  if (p >= header.size()) throw InputError(src + ": malformed .npy header");
  const char open = header[p];
  const char close = open == '\'' ? '\'' : open == '(' ? ')' : ',';
  const std::size_t end = header.find(close, p + 1);
  if (end == std::string::npos) throw InputError(src + ": malformed .npy header");
  if (open == '\'' || open == '(') return header.substr(p + 1, end - p - 1);
  return header.substr(p, end - p);
}

}  // namespace

std::size_t NpyArray::elementCount() const {
  std::size_t n = 1;
  for (std::size_t d : shape)
    n *= d;
  return n;
}

std::vector<float> NpyArray::asFloat() const {
  const std::size_t n = elementCount();
  std::vector<float> out(n);
  const char* p = data.data();
  for (std::size_t i = 0; i < n; ++i) {
    if (dtype == "<f4") {
      std::memcpy(&out[i], p + 4 * i, 4);
    } else if (dtype == "<f8") {
      double v;
      std::memcpy(&v, p + 8 * i, 8);
      out[i] = static_cast<float>(v);
    } else if (dtype == "<i4") {
      std::int32_t v;
      std::memcpy(&v, p + 4 * i, 4);
      out[i] = static_cast<float>(v);
    } else if (dtype == "<i8") {
      std::int64_t v;
      std::memcpy(&v, p + 8 * i, 8);
      out[i] = static_cast<float>(v);
    } else if (itemSize(dtype) == 1) {
      out[i] = static_cast<unsigned char>(p[i]);
    } else {
      throw InputError("unsupported .npy dtype '" + dtype + "'");
    }
  }
  return out;
}

NpyArray parseNpy(const std::string& bytes, const std::string& src) {
  if (bytes.size() < 10 || std::memcmp(bytes.data(), "\x93NUMPY", 6) != 0) {
    throw InputError(src + ": not a .npy file (bad magic)");
  }
  const int major = static_cast<unsigned char>(bytes[6]);
  std::size_t header_len = 0, header_start = 0;
  if (major == 1) {
    header_len = static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw InputError(src + ": truncated .npy header");
    std::uint32_t len;
    std::memcpy(&len, bytes.data() + 8, 4);
    header_len = len;
    header_start = 12;
  } else {
    throw InputError(src + ": unsupported .npy version " + std::to_string(major));
  }
  if (header_start + header_len > bytes.size()) throw InputError(src + ": truncated .npy header");
  const std::string header = bytes.substr(header_start, header_len);
  NpyArray a;
  a.dtype = dictValue(header, "descr", src);
  if (itemSize(a.dtype) == 0) throw InputError(src + ": unsupported .npy dtype '" + a.dtype + "'");
  if (dictValue(header, "fortran_order", src).find("True") != std::string::npos) {
    throw InputError(src + ": Fortran-order .npy arrays are not supported");
  }
  std::stringstream shape(dictValue(header, "shape", src));
  std::string dim;
  std::size_t count = 1;
  while (std::getline(shape, dim, ',')) {
    const std::size_t first = dim.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    // strtoull would read "-1" as 2^64 - 1 and saturate on overflow: digits only, in range.
    const char* digits = dim.c_str() + first;
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(digits, &end, 10);
    if (*digits < '0' || *digits > '9' || errno == ERANGE) {
      throw InputError(src + ": bad .npy shape '" + dim + "'");
    }
    if (v != 0 && count > std::numeric_limits<std::size_t>::max() / v) {
      throw InputError(src + ": .npy shape overflows");
    }
    count *= v;
    a.shape.push_back(v);
  }
  const std::size_t data_start = header_start + header_len;
  const std::size_t item = itemSize(a.dtype);
  if (count > (bytes.size() - data_start) / item) {
    throw InputError(src + ": .npy data is truncated (" +
                     std::to_string(bytes.size() - data_start) + " bytes for " +
                     std::to_string(count) + " elements)");
  }
  a.data.assign(bytes.begin() + data_start, bytes.begin() + data_start + count * item);
  return a;
}

NpyArray readNpy(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseNpy(ss.str(), path);
}

std::string npyHeader(const std::string& dtype, const std::vector<std::size_t>& shape) {
  std::string dict = "{'descr': '" + dtype + "', 'fortran_order': False, 'shape': (";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    dict += std::to_string(shape[i]);
    if (shape.size() == 1 || i + 1 < shape.size()) dict += ",";
    if (i + 1 < shape.size()) dict += " ";
  }
  dict += "), }";
  // Pad so that the data starts on a 64-byte boundary; the header ends with '\n'.
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  std::string out = "\x93NUMPY";
  out += static_cast<char>(1);
  out += static_cast<char>(0);
  out += static_cast<char>(dict.size() & 0xff);
  out += static_cast<char>((dict.size() >> 8) & 0xff);
  return out + dict;
}

namespace {
void writeRaw(const std::string& path, const std::string& dtype, const void* data,
              std::size_t bytes, const std::vector<std::size_t>& shape) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path + ": cannot open for writing");
  const std::string header = npyHeader(dtype, shape);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  if (!out) throw InputError(path + ": write failed");
}
std::size_t product(const std::vector<std::size_t>& shape) {
  std::size_t n = 1;
  for (auto d : shape)
    n *= d;
  return n;
}
}  // namespace

void writeNpy(const std::string& path, const float* data, const std::vector<std::size_t>& shape) {
  writeRaw(path, "<f4", data, product(shape) * 4, shape);
}

void writeNpy(const std::string& path, const std::uint8_t* data,
              const std::vector<std::size_t>& shape) {
  writeRaw(path, "|u1", data, product(shape), shape);
}

}  // namespace io
}  // namespace multimodal_nvs
