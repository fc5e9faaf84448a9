#include "multimodal_nvs/core/common/sparse_dilation.hpp"

#include <algorithm>
#include <cstdlib>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

void dilateSparseByDiamond(const cv::Mat& in, const std::vector<long long>& nonzero, int radius,
                           cv::Mat& out, ThreadPool& pool) {
  if (in.type() != CV_32FC1 || !in.isContinuous()) {
    throw InputError("dilateSparseByDiamond: image must be a continuous CV_32FC1");
  }
  if (radius < 0) throw InputError("dilateSparseByDiamond: radius must be >= 0");
  if (!in.empty() && in.data == out.data) {
    throw InputError("dilateSparseByDiamond: in and out must not share memory");
  }
  const int rows = in.rows, cols = in.cols;
  out.create(rows, cols, CV_32FC1);
  if (rows == 0 || cols == 0) return;
  const long long total = static_cast<long long>(rows) * cols;
  const float* source = in.ptr<float>(0);
  // Row bands, each written by one task from every listed pixel whose diamond reaches it: the
  // maximum does not depend on the order of the writes, so neither does the result on the
  // thread count.
  const int bands = std::min(rows, 4 * pool.size());
  pool.parallelFor(bands, [&](long long b, int) {
    const int r0 = static_cast<int>(b * rows / bands),
              r1 = static_cast<int>((b + 1) * rows / bands);
    for (int y = r0; y < r1; ++y)
      std::fill_n(out.ptr<float>(y), cols, 0.0f);
    for (const long long index : nonzero) {
      if (index < 0 || index >= total) continue;
      const float value = source[index];
      if (!(value > 0.0f)) continue;
      const int r = static_cast<int>(index / cols), c = static_cast<int>(index % cols);
      const int y0 = std::max(r0, r - radius), y1 = std::min(r1 - 1, r + radius);
      for (int y = y0; y <= y1; ++y) {
        const int half = radius - std::abs(y - r);
        float* row = out.ptr<float>(y);
        const int x1 = std::min(cols - 1, c + half);
        for (int x = std::max(0, c - half); x <= x1; ++x)
          row[x] = std::max(row[x], value);
      }
    }
  });
}

}  // namespace multimodal_nvs
