#pragma once
// Rows whose neighbourhood filter output can be copied instead of computed. A filter whose output
// row r depends only on the input rows r - halo .. r + halo (a median, a bilateral filter) gives
// the same output row wherever those 2 halo + 1 rows are identical and equal to the previous such
// window. Why: in a filled LiDAR depth image every column above the highest ring holds the
// column's topmost value (IP-Basic's extension to the top row), so on VoD about half of the rows
// are one repeated row, and filtering each of them again was half of the `ipbasic` smoothing.
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// For each row r of `in`, the row whose filter output row r equals: r itself when it must be
/// computed, else an earlier row r' < r whose window (rows r' - halo .. r' + halo) is byte for
/// byte the same as r's. Only rows with a full window inside the image (halo <= r < rows - halo)
/// are ever copied, so the filter's border rule does not matter.
std::vector<int> repeatedRowSources(const cv::Mat& in, int halo, ThreadPool& pool);

/// Copies into each row r of `out` with source[r] != r the (already filtered) row source[r].
void copyRepeatedRows(const std::vector<int>& source, cv::Mat& out, ThreadPool& pool);

}  // namespace multimodal_nvs
