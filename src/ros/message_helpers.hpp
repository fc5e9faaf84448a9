#pragma once
// Helpers private to the conversion sources (conversions.cpp, renderer_conversions.cpp): error
// texts, and output images shaped in a new or a recycled message.
#include <sensor_msgs/Image.h>
#include <boost/make_shared.hpp>

#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>

#include "multimodal_nvs/core/common/buffer_reuse.hpp"

namespace multimodal_nvs {
namespace ros_conversions {
namespace detail {

/// The parts streamed one after the other: the reasons of rejected inputs.
template <typename... Parts>
std::string concat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

inline bool hostIsBigEndian() {
  const std::uint16_t probe = 1;
  std::uint8_t first_byte;
  std::memcpy(&first_byte, &probe, 1);
  return first_byte == 0;
}

/// Resizes a message's byte buffer to `size`. A buffer of about that size is kept as it is (a
/// recycled output message: no zero-fill, no page faults); one far larger is given back, so that
/// one huge input does not pin its memory for the rest of the run.
template <class ByteVector>
void resizeKeepingBuffer(ByteVector& data, std::size_t size) {
  if (capacityFarExceeds(data.capacity(), size)) ByteVector().swap(data);
  data.resize(size);
}

/// Makes `image` a `rows` x `cols` image of `encoding`, unpadded, in the host's byte order, for
/// the caller to fill (its buffer kept by resizeKeepingBuffer).
inline void shapeImage(sensor_msgs::Image& image, int rows, int cols, const std::string& encoding,
                       std::size_t pixel_bytes, const std_msgs::Header& header) {
  image.header = header;
  image.height = rows;
  image.width = cols;
  image.encoding = encoding;
  image.is_bigendian = hostIsBigEndian();
  image.step = static_cast<std::uint32_t>(cols * pixel_bytes);
  resizeKeepingBuffer(image.data, std::size_t(image.step) * rows);
}

/// A new `rows` x `cols` image of `encoding` (see shapeImage), its data zeroed.
inline sensor_msgs::ImagePtr emptyImage(int rows, int cols, const std::string& encoding,
                                        std::size_t pixel_bytes, const std_msgs::Header& header) {
  auto image = boost::make_shared<sensor_msgs::Image>();
  shapeImage(*image, rows, cols, encoding, pixel_bytes, header);
  return image;
}

}  // namespace detail
}  // namespace ros_conversions
}  // namespace multimodal_nvs
