#pragma once
// The header of a PCD v0.7 file, checked against the bytes that follow it before PCL's reader sees
// the file (io::parsePcd, pcd_reader.cpp).
//
// PCL's PCDReader trusts the header: while reading it, it allocates POINTS x point_step bytes; it
// copies the binary payload without knowing its length; it decompresses binary_compressed data
// into a buffer sized by the size word stored in the payload; it counts an ascii row with the wrong
// number of values as read (the point stays zero); and it keeps parsing header lines after DATA.
// So a 100-byte file could make it allocate gigabytes or read past the end of the input. This check
// runs first: it accepts only what PCL reads the same way and only sizes the bytes can hold.
#include <cstdint>
#include <string>

namespace multimodal_nvs {
namespace io {

enum class PcdEncoding { kAscii, kBinary, kBinaryCompressed };

/// What a checked PCD header promises.
struct PcdLayout {
  PcdEncoding encoding = PcdEncoding::kAscii;
  std::size_t payload_offset = 0;      ///< first byte after the DATA line
  std::uint64_t points = 0;            ///< POINTS, equal to WIDTH * HEIGHT
  std::uint64_t point_step = 0;        ///< bytes per point: the sum of SIZE * COUNT
  std::uint64_t values_per_point = 0;  ///< the sum of COUNT: numbers on each ascii row
};

/// Reads the header strictly (the v0.7 entries in their order, FIELDS, SIZE, TYPE, WIDTH, HEIGHT,
/// POINTS and DATA required, numbers in range, SIZE x TYPE one of I1-I8, U1-U8, F4, F8) and checks
/// the payload against it: binary data long enough, binary_compressed size words consistent with
/// the header and the bytes present, one ascii row of the right length per point. Throws InputError
/// naming `source` and the reason.
PcdLayout checkPcdLayout(const std::string& bytes, const std::string& source);

}  // namespace io
}  // namespace multimodal_nvs
