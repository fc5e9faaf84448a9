#include "multimodal_nvs/core/common/striped_filters.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace multimodal_nvs {
namespace {

constexpr int kMinStripeRows = 32;  // below this the per-call overhead of OpenCV dominates

/// Stripes of at least kMinStripeRows rows, two per worker so that an uneven stripe does not leave
/// a core idle.
int stripeCount(int rows, const ThreadPool& pool) {
  return std::max(1, std::min(2 * pool.size(), rows / kMinStripeRows));
}

template <typename Filter>
void byStripes(const cv::Mat& in, cv::Mat& out, ThreadPool& pool, const Filter& filter) {
  out.create(in.size(), in.type());
  const int rows = in.rows, stripes = stripeCount(rows, pool);
  pool.parallelFor(stripes, [&](long long s, int) {
    const int r0 = static_cast<int>(s * rows / stripes);
    const int r1 = static_cast<int>((s + 1) * rows / stripes);
    cv::Mat target = out.rowRange(r0, r1);  // a header: the filter writes into `out`'s memory
    filter(r0, r1, target);
  });
}

}  // namespace

void stripedDilate(const cv::Mat& in, cv::Mat& out, const cv::Mat& kernel, ThreadPool& pool) {
  byStripes(in, out, pool,
            [&](int r0, int r1, cv::Mat& dst) { cv::dilate(in.rowRange(r0, r1), dst, kernel); });
}

void stripedErode(const cv::Mat& in, cv::Mat& out, const cv::Mat& kernel, ThreadPool& pool) {
  byStripes(in, out, pool,
            [&](int r0, int r1, cv::Mat& dst) { cv::erode(in.rowRange(r0, r1), dst, kernel); });
}

void stripedMedianBlur(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool) {
  const int halo = ksize / 2, rows = in.rows;
  byStripes(in, out, pool, [&](int r0, int r1, cv::Mat& dst) {
    // The stripe with ksize / 2 rows of context on each side: the stripe's rows then see exactly
    // the neighbours they see in the whole image, whether or not cv::medianBlur reads a ROI's
    // parent, and the context's own edges are the image's edges or rows that are thrown away.
    const int top = std::max(0, r0 - halo), bottom = std::min(rows, r1 + halo);
    thread_local cv::Mat filtered;  // kept across frames: no first-touch page faults
    cv::medianBlur(in.rowRange(top, bottom), filtered, ksize);
    filtered.rowRange(r0 - top, r1 - top).copyTo(dst);
  });
}

}  // namespace multimodal_nvs
