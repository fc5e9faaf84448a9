#include "multimodal_nvs/core/common/bilateral_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/repeated_rows.hpp"

namespace multimodal_nvs {
namespace {

constexpr int kRowBlock = 8;  // rows per task

/// exp(x) for x in [-87, 0] (Cephes' single-precision expf: Cody-Waite reduction by ln 2 and a
/// degree-5 polynomial, relative error ~1e-7). Branch-free so that the column loops vectorise; the
/// caller clamps x into range, so 2^n is always a normal float.
inline float expNonPositive(float x) {
  const float n = std::floor(x * 1.44269504088896341f + 0.5f);
  float r = x - n * 0.693359375f;
  r = r - n * -2.12194440e-4f;
  float p = 1.9875691500e-4f;
  p = p * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  const std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return (p * r * r + r + 1.0f) * scale;
}

/// Weight of neighbour value v for centre value c: exp(space_term + color_coeff (v - c)^2), with
/// OpenCV's NaN rules (NaN neighbour: 0, NaN centre: the spatial weight alone). The argument is
/// clamped to [-87, 0] before the exponential (weights below ~1e-38 are zero for the filter), and
/// no NaN reaches the exponential's float-to-int conversion.
inline float neighbourWeight(float v, float c, float space_term, float color_coeff) {
  const float d = v - c;
  float arg = (c == c) ? space_term + color_coeff * d * d : space_term;
  arg = (arg >= -87.0f) ? arg : -87.0f;  // also maps NaN (v NaN, or inf - inf) into range
  const float w = expNonPositive(arg);
  return (v == v) ? w : 0.0f;
}

struct Offset {
  int dy, dx;
  float space_term;  // -r^2 / (2 sigma_space^2)
};

/// Accumulates neighbour `k` of every pixel of row `centre` into sum / wsum.
void accumulateNeighbour(const float* __restrict centre, const float* __restrict neighbours,
                         const Offset& k, int cols, float color_coeff, float* __restrict sum,
                         float* __restrict wsum) {
  // Columns whose neighbour lies inside the row: the vectorised loop.
  const int j0 = std::max(0, -k.dx), j1 = std::min(cols, cols - k.dx);
  const float* shifted = neighbours + k.dx;
  for (int j = j0; j < j1; ++j) {
    const float v = shifted[j];
    const float w = neighbourWeight(v, centre[j], k.space_term, color_coeff);
    wsum[j] += w;
    sum[j] += (v == v) ? w * v : 0.0f;
  }
  // The at most `radius` columns on each side whose neighbour is reflected.
  const auto border = [&](int j) {
    const float v = neighbours[cv::borderInterpolate(j + k.dx, cols, cv::BORDER_REFLECT_101)];
    const float w = neighbourWeight(v, centre[j], k.space_term, color_coeff);
    wsum[j] += w;
    sum[j] += (v == v) ? w * v : 0.0f;
  };
  for (int j = 0; j < std::min(j0, cols); ++j)
    border(j);
  for (int j = std::max(j1, j0); j < cols; ++j)
    border(j);
}

}  // namespace

void bilateralFilterFloat(const cv::Mat& in, cv::Mat& out, int diameter, double sigma_color,
                          double sigma_space, ThreadPool& pool) {
  if (in.type() != CV_32FC1) throw InputError("bilateralFilterFloat: image must be CV_32FC1");
  if (in.data == out.data && !in.empty())
    throw InputError("bilateralFilterFloat: in and out must not share memory");
  // OpenCV's parameter rules.
  if (sigma_color <= 0) sigma_color = 1;
  if (sigma_space <= 0) sigma_space = 1;
  const int radius =
      std::max(1, diameter <= 0 ? static_cast<int>(std::lround(sigma_space * 1.5)) : diameter / 2);
  const double color_coeff = -0.5 / (sigma_color * sigma_color);
  const double space_coeff = -0.5 / (sigma_space * sigma_space);
  std::vector<Offset> offsets;
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const double r2 = double(dy) * dy + double(dx) * dx;
      if (std::sqrt(r2) > radius || (dy == 0 && dx == 0)) continue;
      offsets.push_back({dy, dx, static_cast<float>(r2 * space_coeff)});
    }
  }
  const int rows = in.rows, cols = in.cols;
  out.create(rows, cols, CV_32FC1);
  if (rows == 0 || cols == 0) return;
  const float color = static_cast<float>(color_coeff);
  // Rows whose window repeats an earlier row's (a filled depth image above the highest LiDAR ring)
  // are copied from that row's output instead of filtered again.
  const std::vector<int> source = repeatedRowSources(in, radius, pool);
  const int blocks = (rows + kRowBlock - 1) / kRowBlock;
  pool.parallelFor(blocks, [&](long long b, int) {
    thread_local std::vector<float> buffer;
    buffer.resize(2 * std::size_t(cols));
    float* sum = buffer.data();
    float* wsum = sum + cols;
    const int r0 = static_cast<int>(b) * kRowBlock;
    for (int r = r0; r < std::min(rows, r0 + kRowBlock); ++r) {
      if (source[r] != r) continue;
      const float* centre = in.ptr<float>(r);
      std::fill(buffer.begin(), buffer.end(), 0.0f);
      for (const Offset& k : offsets) {
        const float* neighbours =
            in.ptr<float>(cv::borderInterpolate(r + k.dy, rows, cv::BORDER_REFLECT_101));
        accumulateNeighbour(centre, neighbours, k, cols, color, sum, wsum);
      }
      float* target = out.ptr<float>(r);
      for (int j = 0; j < cols; ++j) {
        const float c = centre[j];
        target[j] = (c == c) ? (sum[j] + c) / (wsum[j] + 1.0f) : sum[j] / wsum[j];
      }
    }
  });
  copyRepeatedRows(source, out, pool);
}

}  // namespace multimodal_nvs
