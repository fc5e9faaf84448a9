#include "multimodal_nvs/core/depth/models/kernel_model.hpp"

// Gaussian kernel regression within the radius: the reference's `kernel` model.
#include <Eigen/Core>
#include <algorithm>
#include <limits>

#include "multimodal_nvs/core/common/simd_buffer.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/models/local_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {
namespace {

// Pixels of one segment handled together: their weights are formed by one vectorised exp.
constexpr int kBlock = 64;

// Weighted mean and variance of the targets for `count` pixels, then stored. Branch-free with
// restrict pointers so that it vectorises: the scalar version spent most of its time waiting on
// two double divisions per pixel.
void storeMoments(const double* __restrict sum_w, const double* __restrict sum_wy,
                  const double* __restrict sum_wyy, int count, float shift,
                  float* __restrict mean_out, float* __restrict variance_out) {
  for (int p = 0; p < count; ++p) {
    const bool supported = sum_w[p] > 0.0;
    const double mean = sum_wy[p] / sum_w[p];
    const double var = std::max(sum_wyy[p] / sum_w[p] - mean * mean, 0.0);
    mean_out[p] = supported ? static_cast<float>(mean) + shift : mean_out[p];
    variance_out[p] = supported ? static_cast<float>(var) : variance_out[p];
  }
}

}  // namespace

void predictKernel(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                   const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                   ThreadPool& pool, PixelPredictions& out) {
  fillPredictions(angles, std::numeric_limits<float>::quiet_NaN(), kNoPrediction, pool, out);
  const std::vector<double> targets = shiftedTargets(samples, shift);
  // float32 weights exactly as the reference forms them: exp((-0.5 * d2) / ls^2).
  const float ls2 =
      static_cast<float>(params.kernel_length_scale_deg * params.kernel_length_scale_deg);
  const float shift32 = static_cast<float>(shift);
  const int cols = angles.grid().cols();

  pool.parallelFor(
      angles.grid().rows(),
      [&](long long row_index, int) {
        const int row = static_cast<int>(row_index);
        const float* az = angles.azimuthRow(row);
        const float* el = angles.elevationRow(row);
        SimdVector<float> weights;
        for (std::size_t k = sets.rowBegin(row); k < sets.rowBegin(row + 1); ++k) {
          const NeighbourSegment& seg = sets.segments()[k];
          const int n = sets.setSize(seg.set_id);
          const int* members = sets.members(seg.set_id);
          for (int c0 = seg.col_begin; c0 < seg.col_end; c0 += kBlock) {
            const int m = std::min(kBlock, seg.col_end - c0);
            // Exponents of the whole n x m block first, then one vectorised exp over all of them.
            // Padded to whole 16-float packets: Eigen's exp then never falls back to scalar expf.
            const std::size_t padded = (std::size_t(n) * m + 15) & ~std::size_t(15);
            weights.resize(padded, 0.0f);
            for (int i = 0; i < n; ++i) {
              const AngularSample& s = samples[members[i]];
              float* w = weights.data() + std::size_t(i) * m;
              for (int p = 0; p < m; ++p) {
                const float da = az[c0 + p] - s.azimuth_deg;
                const float de = el[c0 + p] - s.elevation_deg;
                const float d2 = da * da + de * de;
                w[p] = (-0.5f * d2) / ls2;
              }
            }
            Eigen::Map<Eigen::ArrayXf> block(weights.data(), padded);
            block = block.exp();
            // Segments average about 15 pixels: clear only the m accumulators in use.
            double sum_w[kBlock], sum_wy[kBlock], sum_wyy[kBlock];
            std::fill_n(sum_w, m, 0.0);
            std::fill_n(sum_wy, m, 0.0);
            std::fill_n(sum_wyy, m, 0.0);
            for (int i = 0; i < n; ++i) {
              const float* w = weights.data() + std::size_t(i) * m;
              const double y = targets[members[i]];
              for (int p = 0; p < m; ++p) {
                sum_w[p] += w[p];
                sum_wy[p] += w[p] * y;
                sum_wyy[p] += w[p] * y * y;
              }
            }
            const std::size_t pixel = std::size_t(row) * cols + c0;
            storeMoments(sum_w, sum_wy, sum_wyy, m, shift32, out.mean.data() + pixel,
                         out.variance.data() + pixel);
          }
        }
      },
      4);
}

}  // namespace multimodal_nvs
