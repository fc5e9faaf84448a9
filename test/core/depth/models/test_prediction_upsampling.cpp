// A prediction on a coarser grid interpolated onto the output grid: inverse depth that is affine
// in the image (a plane, such as the road) and a variance that is affine come out exact up to
// rounding, the coarse samples are kept where the grids meet, and past the coarse grid's last row
// and column the edge value holds.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "multimodal_nvs/core/depth/models/prediction_upsampling.hpp"

namespace mm = multimodal_nvs;

TEST(PredictionUpsampling, AffineInverseDepthAndVarianceComeOutExact) {
  const mm::ImageSize image{37, 53};  // not a multiple of the factor: edge rows and columns
  for (const int factor : {1, 2, 4}) {
    const mm::StrideGrid grid{image, 1}, coarse_grid{image, factor};
    const auto inverse_depth = [](double u, double v) { return 0.02 + 0.001 * u + 0.003 * v; };
    const auto variance = [](double u, double v) { return 1.0 + 0.5 * u - 0.25 * v; };
    mm::PixelPredictions coarse;
    for (int r = 0; r < coarse_grid.rows(); ++r) {
      for (int c = 0; c < coarse_grid.cols(); ++c) {
        coarse.mean.push_back(static_cast<float>(1.0 / inverse_depth(c * factor, r * factor)));
        coarse.variance.push_back(static_cast<float>(variance(c * factor, r * factor)));
      }
    }
    mm::ThreadPool pool(2);
    mm::PixelPredictions out;
    mm::upsamplePredictions(coarse, coarse_grid, grid, factor, pool, out);
    ASSERT_EQ(out.mean.size(), std::size_t(grid.size()));
    const int last_row = (coarse_grid.rows() - 1) * factor;
    const int last_col = (coarse_grid.cols() - 1) * factor;
    for (int r = 0; r < grid.rows(); ++r) {
      for (int c = 0; c < grid.cols(); ++c) {
        const std::size_t i = std::size_t(r) * grid.cols() + c;
        // Past the last coarse row or column: that row's or column's value.
        const double u = std::min(c, last_col), v = std::min(r, last_row);
        ASSERT_NEAR(out.mean[i], 1.0 / inverse_depth(u, v), 1e-5 / inverse_depth(u, v))
            << "factor " << factor << " at " << r << ", " << c;
        ASSERT_NEAR(out.variance[i], variance(u, v), 1e-4) << "factor " << factor;
        if (r % factor == 0 && c % factor == 0) {
          const std::size_t j = std::size_t(r / factor) * coarse_grid.cols() + c / factor;
          ASSERT_FLOAT_EQ(out.mean[i], coarse.mean[j]);
          ASSERT_FLOAT_EQ(out.variance[i], coarse.variance[j]);
        }
      }
    }
  }
}

// Between a near and a far sample the depth is the inverse of the blended inverse depths: nearer
// than the blended depths (a plane seen in perspective), never a value outside the two.
TEST(PredictionUpsampling, DepthBetweenTwoSamplesBlendsTheirInverses) {
  const mm::ImageSize image{1, 3};
  const mm::StrideGrid grid{image, 1}, coarse_grid{image, 2};
  mm::PixelPredictions coarse{{10.0f, 40.0f}, {1.0f, 3.0f}};
  mm::ThreadPool pool(1);
  mm::PixelPredictions out;
  mm::upsamplePredictions(coarse, coarse_grid, grid, 2, pool, out);
  EXPECT_FLOAT_EQ(out.mean[1], 1.0f / (0.5f / 10.0f + 0.5f / 40.0f));  // 16 m, not 25
  EXPECT_FLOAT_EQ(out.variance[1], 2.0f);
  EXPECT_FLOAT_EQ(out.mean[2], 40.0f);
}

// Read row by row as each row is interpolated (what image_guided does with ground_gp's coarser
// prior) the values are those upsamplePredictions writes, bit for bit; a stored prediction is read
// in place.
TEST(PredictionUpsampling, RowsReadWhenInterpolatedAreTheWrittenPlanes) {
  const mm::ImageSize image{29, 45};
  const mm::StrideGrid grid{image, 1}, coarse_grid{image, 4};
  mm::PixelPredictions coarse;
  for (int i = 0; i < coarse_grid.size(); ++i) {
    coarse.mean.push_back(3.0f + 0.37f * float(i % 11) + 0.11f * float(i % 7));
    coarse.variance.push_back(0.5f + 0.013f * float(i % 13));
  }
  mm::ThreadPool pool(2);
  mm::PixelPredictions written;
  mm::upsamplePredictions(coarse, coarse_grid, grid, 4, pool, written);
  mm::UpsampledPredictions upsampled;
  upsampled.prepare(coarse, coarse_grid, grid, 4, pool);
  const mm::PredictionRows interpolated(upsampled);
  const mm::PredictionRows stored(written, grid.rows(), grid.cols());
  ASSERT_EQ(interpolated.rows(), grid.rows());
  ASSERT_EQ(interpolated.cols(), grid.cols());
  std::vector<float> scratch(grid.cols());
  for (int r = 0; r < grid.rows(); ++r) {
    const std::size_t at = std::size_t(r) * grid.cols();
    const float* mean = interpolated.mean(r, scratch.data());
    EXPECT_EQ(mean, scratch.data());
    for (int c = 0; c < grid.cols(); ++c)
      ASSERT_EQ(mean[c], written.mean[at + c]) << r << ", " << c;
    const float* variance = interpolated.variance(r, scratch.data());
    for (int c = 0; c < grid.cols(); ++c)
      ASSERT_EQ(variance[c], written.variance[at + c]) << r << ", " << c;
    EXPECT_EQ(stored.mean(r, scratch.data()), written.mean.data() + at);
    EXPECT_EQ(stored.variance(r, scratch.data()), written.variance.data() + at);
  }
  // A stored prediction of another size is refused, not read past its end.
  EXPECT_THROW(mm::PredictionRows(written, grid.rows() + 1, grid.cols()), std::invalid_argument);
}
