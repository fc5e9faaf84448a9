#pragma once
// OpenCV neighbourhood filters run as row stripes on the package's thread pool. Why: Debian's
// OpenCV 4.6 runs cv::dilate / cv::erode and cv::medianBlur on one thread (measured: the same time
// with cv::setNumThreads(1) and (2) on a 1936x1216 float image), and they are most of the `ipbasic`
// baseline. Every stripe computes exactly the rows the whole-image call would, so the outputs are
// bit-identical to it for any thread count (test_striped_filters compares them).
#include <opencv2/core.hpp>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// cv::dilate(in, out, kernel) (default anchor, one iteration, default border) by row stripes.
/// `in` may be a ROI: as in OpenCV, pixels outside it are read from its parent. `out` must not
/// share memory with `in`.
void stripedDilate(const cv::Mat& in, cv::Mat& out, const cv::Mat& kernel, ThreadPool& pool);

/// cv::medianBlur(in, out, ksize) by row stripes, each filtered with ksize / 2 rows of context on
/// each side. `in` is treated as a whole image (its parent, if any, is not read), as OpenCV does.
/// A row whose window repeats an earlier row's (repeatedRowSources) is copied, not filtered.
void stripedMedianBlur(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool);

/// cv::morphologyEx(in, out, op, kernel, default anchor, iterations) for op MORPH_DILATE,
/// MORPH_ERODE, MORPH_OPEN or MORPH_CLOSE with a kernel of odd size, on the image `in` (its
/// parent, if any, is not read). Each stripe runs all passes with enough rows of context for its
/// own rows to be exact, in a block small enough to stay in cache: several passes (a diamond as
/// iterations of the cross, a closing) then cost about one pass of memory traffic.
void stripedMorphology(const cv::Mat& in, cv::Mat& out, int op, const cv::Mat& kernel,
                       int iterations, ThreadPool& pool);

}  // namespace multimodal_nvs
