#pragma once
// numpy .npy arrays: reading (versions 1-3) and writing float32 / uint8.
#include <cstdint>
#include <string>
#include <vector>

namespace multimodal_nvs {
namespace io {

/// A C-order .npy array as read from disk: dtype descriptor ('<f4', '|u1', ...), shape, raw bytes.
struct NpyArray {
  std::string dtype;
  std::vector<std::size_t> shape;
  std::vector<char> data;

  std::size_t elementCount() const;
  /// Converts to float32 from <f4, <f8, |u1, |b1, <i4, <i8; throws InputError otherwise.
  std::vector<float> asFloat() const;
};

/// Reads a version 1/2/3 .npy file. Throws InputError naming the file on any format problem.
NpyArray readNpy(const std::string& path);
NpyArray parseNpy(const std::string& bytes, const std::string& source);

/// Writes a C-order little-endian array. Throws InputError when the file cannot be written.
void writeNpy(const std::string& path, const float* data, const std::vector<std::size_t>& shape);
void writeNpy(const std::string& path, const std::uint8_t* data,
              const std::vector<std::size_t>& shape);
/// The header bytes of a v1.0 .npy (for streaming large arrays); `dtype` like "<f4".
std::string npyHeader(const std::string& dtype, const std::vector<std::size_t>& shape);

}  // namespace io
}  // namespace multimodal_nvs
