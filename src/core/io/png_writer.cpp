#include "multimodal_nvs/core/io/png_writer.hpp"

#include <libdeflate.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"

// Why not cv::imwrite: OpenCV's PNG path (libpng + zlib) took ~24 ms per 704x1280 conditioning
// frame at its fastest settings, the largest single CPU cost of a 121-frame GEN3C export. The
// container is four fixed records (PNG specification, ISO/IEC 15948: signature, IHDR, one IDAT
// holding a zlib stream, IEND, each chunk with a CRC-32); the compression and both checksums are
// libdeflate's.

namespace multimodal_nvs {
namespace io {
namespace {

void appendBigEndian(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<std::uint8_t>(value >> shift));
}

/// A chunk: length, type, data, CRC-32 over type and data.
void appendChunk(std::vector<std::uint8_t>& out, const char (&type)[5], const std::uint8_t* data,
                 std::size_t size) {
  appendBigEndian(out, static_cast<std::uint32_t>(size));
  const std::size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  appendBigEndian(out, libdeflate_crc32(0, out.data() + type_at, 4 + size));
}

struct CompressorDeleter {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

}  // namespace

void writePng(const std::string& path, const cv::Mat& image, int level) {
  const int channels = image.channels();
  if (image.empty() || image.depth() != CV_8U || (channels != 1 && channels != 3) ||
      image.dims != 2) {
    throw InputError(path + ": a PNG is written from an 8-bit gray or BGR image");
  }
  if (level < kPngStored || level > kPngMaxLevel) {
    throw InputError(path + ": PNG compression level " + std::to_string(level) +
                     " is outside [0, 12]");
  }
  const std::size_t row_bytes = static_cast<std::size_t>(image.cols) * channels;
  // The filtered rows: a filter-type byte (0, None) and the row in RGB order.
  // Uninitialised buffers (every byte is written before it is read): zeroing megabytes per frame
  // would be one more pass over memory.
  const std::size_t rows_size = static_cast<std::size_t>(image.rows) * (row_bytes + 1);
  const std::unique_ptr<std::uint8_t[]> rows(new std::uint8_t[rows_size]);
  std::uint8_t* out = rows.get();
  for (int r = 0; r < image.rows; ++r) {
    *out++ = 0;
    const std::uint8_t* in = image.ptr<std::uint8_t>(r);
    if (channels == 1) {
      std::memcpy(out, in, row_bytes);
      out += row_bytes;
    } else {
      for (int c = 0; c < image.cols; ++c, in += 3) {
        *out++ = in[2];
        *out++ = in[1];
        *out++ = in[0];
      }
    }
  }
  const std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor(
      libdeflate_alloc_compressor(level));
  if (!compressor) throw InputError(path + ": cannot allocate the PNG compressor");
  const std::size_t bound = libdeflate_zlib_compress_bound(compressor.get(), rows_size);
  const std::unique_ptr<std::uint8_t[]> zlib(new std::uint8_t[bound]);
  const std::size_t zlib_size =
      libdeflate_zlib_compress(compressor.get(), rows.get(), rows_size, zlib.get(), bound);
  if (zlib_size == 0) throw InputError(path + ": PNG compression failed");

  // Signature and IHDR; the IDAT's length and type, its data straight from the compressor's
  // buffer (a frame is megabytes: no copy into one file buffer), its CRC; IEND.
  std::vector<std::uint8_t> head{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header;
  appendBigEndian(header, static_cast<std::uint32_t>(image.cols));
  appendBigEndian(header, static_cast<std::uint32_t>(image.rows));
  // Bit depth 8; colour type 0 (gray) or 2 (RGB); compression, filter method, interlace: 0.
  const std::array<std::uint8_t, 5> format{8, static_cast<std::uint8_t>(channels == 1 ? 0 : 2), 0,
                                           0, 0};
  header.insert(header.end(), format.begin(), format.end());
  appendChunk(head, "IHDR", header.data(), header.size());
  appendBigEndian(head, static_cast<std::uint32_t>(zlib_size));
  const char idat[] = "IDAT";
  head.insert(head.end(), idat, idat + 4);
  std::vector<std::uint8_t> tail;
  appendBigEndian(tail, libdeflate_crc32(libdeflate_crc32(0, idat, 4), zlib.get(), zlib_size));
  appendChunk(tail, "IEND", nullptr, 0);

  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  if (!stream) throw InputError(path + ": cannot open for writing");
  stream.write(reinterpret_cast<const char*>(head.data()),
               static_cast<std::streamsize>(head.size()));
  stream.write(reinterpret_cast<const char*>(zlib.get()), static_cast<std::streamsize>(zlib_size));
  stream.write(reinterpret_cast<const char*>(tail.data()),
               static_cast<std::streamsize>(tail.size()));
  stream.close();
  if (!stream) throw InputError(path + ": write failed");
}

}  // namespace io
}  // namespace multimodal_nvs
