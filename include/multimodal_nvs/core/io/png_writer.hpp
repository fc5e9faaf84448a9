#pragma once
// PNG files written for speed: libdeflate for the zlib stream, the container by hand.
#include <string>

#include <opencv2/core/mat.hpp>

namespace multimodal_nvs {
namespace io {

/// libdeflate's levels: 0 stores the rows uncompressed (a 704x1280 BGR frame in ~2 ms, 2.7 MB),
/// 1 is the fastest compression (~15 ms, ~1.3 MB), 12 the smallest file.
constexpr int kPngStored = 0;
constexpr int kPngMaxLevel = 12;

/// Writes an 8-bit gray (CV_8UC1) or BGR (CV_8UC3) image as a PNG that every decoder reads (colour
/// type 0 or 2, bit depth 8, no interlace, filter "None" on every row), honouring the Mat's row
/// step. Throws InputError naming the file for another type, an empty image, a level outside
/// [0, kPngMaxLevel] or a failed write.
void writePng(const std::string& path, const cv::Mat& image, int level = kPngStored);

}  // namespace io
}  // namespace multimodal_nvs
