#include "multimodal_nvs/core/common/repeated_rows.hpp"

#include <algorithm>
#include <cstring>

namespace multimodal_nvs {

std::vector<int> repeatedRowSources(const cv::Mat& in, int halo, ThreadPool& pool) {
  const int rows = in.rows;
  std::vector<int> source(static_cast<std::size_t>(std::max(0, rows)));
  for (int r = 0; r < rows; ++r)
    source[r] = r;
  // With halo 0 two equal windows need not be equal rows: nothing is copied.
  if (rows < 2 || halo < 1) return source;
  // same_as_next[r]: row r and row r + 1 hold the same bytes.
  const std::size_t row_bytes = in.cols * in.elemSize();
  std::vector<char> same_as_next(rows, 0);
  constexpr int kRowsPerTask = 64;
  pool.parallelFor((rows - 1 + kRowsPerTask - 1) / kRowsPerTask, [&](long long t, int) {
    const int r0 = static_cast<int>(t) * kRowsPerTask;
    for (int r = r0; r < std::min(rows - 1, r0 + kRowsPerTask); ++r)
      same_as_next[r] = std::memcmp(in.ptr(r), in.ptr(r + 1), row_bytes) == 0;
  });
  // equal_run[i]: how many comparisons up to and including i hold in a row. Row r's window is one
  // repeated row when the 2 halo comparisons r - halo .. r + halo - 1 hold; consecutive such rows
  // share their window's content, so each copies the first row of its run.
  std::vector<int> equal_run(rows - 1, 0);
  for (int i = 0; i < rows - 1; ++i)
    equal_run[i] = same_as_next[i] ? (i > 0 ? equal_run[i - 1] : 0) + 1 : 0;
  int run_start = -1;
  for (int r = 0; r < rows; ++r) {
    const bool repeated = r >= halo && r + halo < rows && equal_run[r + halo - 1] >= 2 * halo;
    if (!repeated) {
      run_start = -1;
    } else if (run_start < 0) {
      run_start = r;  // computed; the rows after it in the run copy it
    } else {
      source[r] = run_start;
    }
  }
  return source;
}

void copyRepeatedRows(const std::vector<int>& source, cv::Mat& out, ThreadPool& pool) {
  const int rows = std::min(out.rows, static_cast<int>(source.size()));
  const std::size_t row_bytes = out.cols * out.elemSize();
  constexpr int kRowsPerTask = 64;
  pool.parallelFor((rows + kRowsPerTask - 1) / kRowsPerTask, [&](long long t, int) {
    const int r0 = static_cast<int>(t) * kRowsPerTask;
    for (int r = r0; r < std::min(rows, r0 + kRowsPerTask); ++r) {
      if (source[r] != r) std::memcpy(out.ptr(r), out.ptr(source[r]), row_bytes);
    }
  });
}

}  // namespace multimodal_nvs
