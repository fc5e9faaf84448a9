#pragma once
// Shared by the harnesses and the seed writer: how a fuzz input becomes a PointCloud2 or an Image
// (and back, so that seeds are real messages), and the one exception type a reader may throw.
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace mmnvs_fuzz {

/// Little-endian fields from the front of the input; reads past the end give 0, so every input,
/// however short, is a message.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  template <typename T>
  T take() {
    T value{};
    const std::size_t n = sizeof(T) < size_ - pos_ ? sizeof(T) : size_ - pos_;
    if (n > 0) std::memcpy(&value, data_ + pos_, n);
    pos_ += n;
    return value;
  }
  std::string takeString(std::size_t length) {
    const std::size_t n = length < size_ - pos_ ? length : size_ - pos_;
    std::string out(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return out;
  }
  const std::uint8_t* rest() const { return data_ + pos_; }
  std::size_t restSize() const { return size_ - pos_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Limits keep the encoding dense (most byte values mean something) without restricting what the
// converter must handle: any field list longer than a few entries exercises nothing new.
constexpr unsigned kMaxFields = 8;
constexpr unsigned kMaxFieldName = 4;

/// Layout: height, width, point_step, row_step (u32), is_bigendian, is_dense, field count (u8),
/// per field: name length (u8) and name, offset (u32), datatype (u8), count (u32); the rest is
/// `data`.
inline sensor_msgs::PointCloud2 cloudFromBytes(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  sensor_msgs::PointCloud2 cloud;
  cloud.height = in.take<std::uint32_t>();
  cloud.width = in.take<std::uint32_t>();
  cloud.point_step = in.take<std::uint32_t>();
  cloud.row_step = in.take<std::uint32_t>();
  cloud.is_bigendian = in.take<std::uint8_t>();
  cloud.is_dense = in.take<std::uint8_t>();
  const unsigned fields = in.take<std::uint8_t>() % (kMaxFields + 1);
  for (unsigned i = 0; i < fields; ++i) {
    sensor_msgs::PointField field;
    field.name = in.takeString(in.take<std::uint8_t>() % (kMaxFieldName + 1));
    field.offset = in.take<std::uint32_t>();
    field.datatype = in.take<std::uint8_t>();
    field.count = in.take<std::uint32_t>();
    cloud.fields.push_back(field);
  }
  cloud.data.assign(in.rest(), in.rest() + in.restSize());
  return cloud;
}

template <typename T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

/// The inverse of cloudFromBytes for clouds within its limits (seed corpus).
inline std::string bytesFromCloud(const sensor_msgs::PointCloud2& cloud) {
  std::string out;
  put<std::uint32_t>(out, cloud.height);
  put<std::uint32_t>(out, cloud.width);
  put<std::uint32_t>(out, cloud.point_step);
  put<std::uint32_t>(out, cloud.row_step);
  put<std::uint8_t>(out, cloud.is_bigendian);
  put<std::uint8_t>(out, cloud.is_dense);
  put<std::uint8_t>(out, static_cast<std::uint8_t>(cloud.fields.size()));
  for (const auto& field : cloud.fields) {
    put<std::uint8_t>(out, static_cast<std::uint8_t>(field.name.size()));
    out += field.name;
    put<std::uint32_t>(out, field.offset);
    put<std::uint8_t>(out, field.datatype);
    put<std::uint32_t>(out, field.count);
  }
  out.append(reinterpret_cast<const char*>(cloud.data.data()), cloud.data.size());
  return out;
}

/// The encodings an image input can name: the five the node reads, and two it must refuse.
inline const char* const kImageEncodings[] = {"rgb8",  "bgr8",  "rgba8", "bgra8",
                                              "mono8", "16UC1", ""};
constexpr unsigned kImageEncodingCount = sizeof(kImageEncodings) / sizeof(kImageEncodings[0]);

/// Layout: encoding index (u8, modulo the list), height, width, step (u32); the rest is `data`.
inline sensor_msgs::Image imageFromBytes(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  sensor_msgs::Image image;
  image.encoding = kImageEncodings[in.take<std::uint8_t>() % kImageEncodingCount];
  image.height = in.take<std::uint32_t>();
  image.width = in.take<std::uint32_t>();
  image.step = in.take<std::uint32_t>();
  image.data.assign(in.rest(), in.rest() + in.restSize());
  return image;
}

/// The inverse of imageFromBytes (seed corpus); `encoding` is an index into kImageEncodings.
inline std::string bytesFromImage(const sensor_msgs::Image& image, std::uint8_t encoding) {
  std::string out;
  put<std::uint8_t>(out, encoding);
  put<std::uint32_t>(out, image.height);
  put<std::uint32_t>(out, image.width);
  put<std::uint32_t>(out, image.step);
  out.append(reinterpret_cast<const char*>(image.data.data()), image.data.size());
  return out;
}

/// A violated invariant: abort so that libFuzzer records the input like any other crash.
#define MMNVS_FUZZ_CHECK(condition)                                                            \
  do {                                                                                         \
    if (!(condition)) {                                                                        \
      std::fprintf(stderr, "%s:%d: invariant violated: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                            \
    }                                                                                          \
  } while (0)

}  // namespace mmnvs_fuzz
