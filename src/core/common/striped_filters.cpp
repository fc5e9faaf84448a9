#include "multimodal_nvs/core/common/striped_filters.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/common/repeated_rows.hpp"

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

/// Runs `filter(context, filtered)` on the rows of each stripe plus `halo` rows of context on each
/// side (fewer at the image's top and bottom, which are the image's own edges), and copies the
/// stripe's rows of the result into `out`. Exact when no output row depends on rows more than
/// `halo` away. Stripes are at most `stripe_rows` high: small enough for the context and the result
/// to stay in the core's L2 cache while a filter makes several passes over them. With `source`
/// (repeatedRowSources), only the rows that are their own source are filtered; the others are
/// copied from their source row's output afterwards.
template <typename Filter>
void byStripesWithContext(const cv::Mat& in, cv::Mat& out, int halo, int stripe_rows,
                          ThreadPool& pool, const Filter& filter,
                          const std::vector<int>* source = nullptr) {
  const int rows = in.rows;
  out.create(in.size(), in.type());
  // Stripes over the rows to compute: each maximal run of such rows cut into pieces of about
  // stripe_rows.
  const auto computed = [&](int r) { return source == nullptr || (*source)[r] == r; };
  std::vector<std::pair<int, int>> stripes;
  const int height = std::max(1, stripe_rows);
  for (int r = 0; r < rows;) {
    if (!computed(r)) {
      ++r;
      continue;
    }
    int end = r + 1;
    while (end < rows && computed(end))
      ++end;
    const int pieces = std::max(1, (end - r) / height);
    for (int p = 0; p < pieces; ++p)
      stripes.emplace_back(r + p * (end - r) / pieces, r + (p + 1) * (end - r) / pieces);
    r = end;
  }
  pool.parallelFor(static_cast<long long>(stripes.size()), [&](long long s, int) {
    const auto [r0, r1] = stripes[s];
    const int top = std::max(0, r0 - halo), bottom = std::min(rows, r1 + halo);
    thread_local cv::Mat filtered;  // kept across frames: no first-touch page faults
    filter(in.rowRange(top, bottom), filtered);
    filtered.rowRange(r0 - top, r1 - top).copyTo(out.rowRange(r0, r1));
  });
  if (source != nullptr) copyRepeatedRows(*source, out, pool);
}

}  // namespace

void stripedDilate(const cv::Mat& in, cv::Mat& out, const cv::Mat& kernel, ThreadPool& pool) {
  byStripes(in, out, pool,
            [&](int r0, int r1, cv::Mat& dst) { cv::dilate(in.rowRange(r0, r1), dst, kernel); });
}

void stripedMedianBlur(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool) {
  // Whether or not cv::medianBlur reads a ROI's parent, the stripe's rows see exactly the
  // neighbours they see in the whole image. Rows whose window repeats an earlier row's are copied.
  const std::vector<int> source = repeatedRowSources(in, ksize / 2, pool);
  byStripesWithContext(
      in, out, ksize / 2, std::max(kMinStripeRows, in.rows / (2 * pool.size())), pool,
      [&](const cv::Mat& context, cv::Mat& filtered) { cv::medianBlur(context, filtered, ksize); },
      &source);
}

void stripedMorphology(const cv::Mat& in, cv::Mat& out, int op, const cv::Mat& kernel,
                       int iterations, ThreadPool& pool) {
  const int passes = iterations * (op == cv::MORPH_CLOSE || op == cv::MORPH_OPEN ? 2 : 1);
  const int halo = passes * (kernel.rows / 2);
  constexpr int kCacheStripeRows = 48;  // 48 x 1936 floats: 370 kB with context and result
  byStripesWithContext(in, out, halo, std::max(kCacheStripeRows, 4 * halo), pool,
                       [&](const cv::Mat& context, cv::Mat& filtered) {
                         cv::morphologyEx(context, filtered, op, kernel, cv::Point(-1, -1),
                                          iterations);
                       });
}

}  // namespace multimodal_nvs
