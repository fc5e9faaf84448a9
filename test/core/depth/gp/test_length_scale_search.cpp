// The batched length-scale search: a set's result does not depend on the sets sharing its batch,
// and the single-precision likelihood (ground_gp's residual GP) agrees with the double one, on
// random sets of 3 to 32 returns within the 2 degree radius at ground_gp's residual amplitude.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/gp/length_scale_search.hpp"

namespace mm = multimodal_nvs;

namespace {

/// `count` random sets of `n` returns: angles within +-2 degrees, residuals in [-3, 0] m (ground_gp
/// clips its residuals to at most 0 and at least -3 amplitudes).
struct RandomSets {
  std::vector<std::vector<float>> az, el;
  std::vector<std::vector<double>> y;

  RandomSets(int n, int count, std::mt19937& rng) {
    std::uniform_real_distribution<float> angle(-2.0f, 2.0f);
    std::uniform_real_distribution<double> residual(-3.0, 0.0);
    for (int s = 0; s < count; ++s) {
      az.emplace_back(n);
      el.emplace_back(n);
      y.emplace_back(n);
      for (int i = 0; i < n; ++i) {
        az[s][i] = angle(rng);
        el[s][i] = angle(rng);
        y[s][i] = residual(rng);
      }
    }
  }
  const float* azOf(int s) const { return az[s].data(); }
  const float* elOf(int s) const { return el[s].data(); }
  const double* yOf(int s) const { return y[s].data(); }
};

mm::LocalGpParams residualParams() {
  mm::DepthCompletionParams params;
  mm::LocalGpParams gp = params.gp;
  gp.amplitude = params.ground.residual_amplitude;
  return gp;
}

/// One set searched alone (one lane).
template <typename Search>
double searchAlone(const mm::LocalGpParams& gp, const RandomSets& sets, int s, int n) {
  Search search(gp);
  const float* az = sets.azOf(s);
  const float* el = sets.elOf(s);
  const double* y = sets.yOf(s);
  double length_scale = 0.0;
  search.search(n, 1, &az, &el, &y, &length_scale);
  return length_scale;
}

template <typename Search>
void expectBatchMatesChangeNothing() {
  const mm::LocalGpParams gp = residualParams();
  constexpr int kLanes = Search::kLanes;
  std::mt19937 rng(3);
  int compared = 0;
  for (int n : {3, 4, 7, 16, 17, 32}) {
    const RandomSets sets(n, kLanes, rng);
    Search search(gp);
    const float* az[kLanes];
    const float* el[kLanes];
    const double* y[kLanes];
    for (int s = 0; s < kLanes; ++s) {
      az[s] = sets.azOf(s);
      el[s] = sets.elOf(s);
      y[s] = sets.yOf(s);
    }
    double batched[kLanes];
    search.search(n, kLanes, az, el, y, batched);
    for (int s = 0; s < kLanes; ++s) {
      EXPECT_EQ(batched[s], searchAlone<Search>(gp, sets, s, n)) << "n " << n << " set " << s;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 6 * kLanes);
}

TEST(LengthScaleSearch, BatchMatesChangeNothingDouble) {
  expectBatchMatesChangeNothing<mm::LengthScaleSearch>();
}

TEST(LengthScaleSearch, BatchMatesChangeNothingSingle) {
  expectBatchMatesChangeNothing<mm::SingleLengthScaleSearch>();
}

// The float likelihood agrees with the double one to float rounding of a well-conditioned kernel
// (residual amplitude 1 m, noise 0.5 m: condition number below 33 / 0.25), across the search range.
TEST(LengthScaleSearch, SingleLikelihoodAgreesWithDouble) {
  const mm::LocalGpParams gp = residualParams();
  std::mt19937 rng(7);
  int compared = 0;
  for (int n = 3; n <= mm::LengthScaleSearch::kMaxBatchedSize; ++n) {
    const RandomSets sets(n, 1, rng);
    const float* az = sets.azOf(0);
    const float* el = sets.elOf(0);
    const double* y = sets.yOf(0);
    mm::LengthScaleSearch search64(gp);
    mm::SingleLengthScaleSearch search32(gp);
    search64.load(n, 1, &az, &el, &y);
    search32.load(n, 1, &az, &el, &y);
    for (double l : {gp.length_scale_min, 0.3, 1.0, 3.0, gp.length_scale_max}) {
      double scales64[mm::LengthScaleSearch::kLanes], scales32[mm::SingleLengthScaleSearch::kLanes];
      std::fill(std::begin(scales64), std::end(scales64), l);
      std::fill(std::begin(scales32), std::end(scales32), l);
      double nll64[mm::LengthScaleSearch::kLanes], nll32[mm::SingleLengthScaleSearch::kLanes];
      search64.negLogMarginalLikelihood(scales64, nll64);
      search32.negLogMarginalLikelihood(scales32, nll32);
      ASSERT_TRUE(std::isfinite(nll64[0])) << "n " << n << " l " << l;
      ASSERT_TRUE(std::isfinite(nll32[0])) << "n " << n << " l " << l;
      EXPECT_NEAR(nll32[0], nll64[0], 1e-4 * (1.0 + std::abs(nll64[0]))) << "n " << n << " l " << l;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 30 * 5);
}

// Where the likelihood is flat the two searches may stop at different length scales; what must
// hold is that the float search's answer is as likely (under the double likelihood) as the double
// search's, to within the bracket's tolerance.
TEST(LengthScaleSearch, SingleSearchFindsAsLikelyALengthScale) {
  mm::LocalGpParams gp = residualParams();
  gp.tolerance = 0.05;  // ground_gp's residual search tolerance
  std::mt19937 rng(13);
  int compared = 0;
  int equal = 0;
  for (int n = 3; n <= mm::LengthScaleSearch::kMaxBatchedSize; ++n) {
    const RandomSets sets(n, 4, rng);
    for (int s = 0; s < 4; ++s) {
      const double l64 = searchAlone<mm::LengthScaleSearch>(gp, sets, s, n);
      const double l32 = searchAlone<mm::SingleLengthScaleSearch>(gp, sets, s, n);
      ASSERT_GE(l32, gp.length_scale_min);
      ASSERT_LE(l32, gp.length_scale_max);
      const float* az = sets.azOf(s);
      const float* el = sets.elOf(s);
      const double* y = sets.yOf(s);
      mm::LengthScaleSearch search64(gp);
      search64.load(n, 1, &az, &el, &y);
      double scales[mm::LengthScaleSearch::kLanes], nll[mm::LengthScaleSearch::kLanes];
      std::fill(std::begin(scales), std::end(scales), l64);
      search64.negLogMarginalLikelihood(scales, nll);
      const double at64 = nll[0];
      std::fill(std::begin(scales), std::end(scales), l32);
      search64.negLogMarginalLikelihood(scales, nll);
      const double at32 = nll[0];
      EXPECT_LE(at32, at64 + 1e-3 * (1.0 + std::abs(at64)))
          << "n " << n << " set " << s << ": l " << l32 << " against " << l64;
      equal += std::abs(l32 - l64) <= gp.tolerance;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 30 * 4);
  // Most sets have one clear minimum, which both searches find.
  EXPECT_GE(equal, compared * 9 / 10);
}

}  // namespace

namespace {

/// A lane whose kernel is singular (two returns at the same angles, no noise) reports +inf, and
/// its batch mates keep the likelihood they have without it.
template <typename Search>
void expectSingularLaneIsInfinite() {
  mm::LocalGpParams gp;
  gp.amplitude = 5.0;  // K = 25 [[1, 1], [1, 1]]: the second pivot is exactly 0
  gp.noise = 0.0;
  constexpr int kLanes = Search::kLanes;
  constexpr int kSingular = 3;
  const std::vector<float> spread_az = {-1.5f, 0.0f, 1.5f}, spread_el = {1.5f, -1.5f, 0.0f};
  const std::vector<float> same_az = {0.5f, 0.5f, -1.0f}, same_el = {0.25f, 0.25f, 1.0f};
  const std::vector<double> y = {-1.0, -2.0, -0.5};
  const float* az[kLanes];
  const float* el[kLanes];
  const double* ys[kLanes];
  for (int s = 0; s < kLanes; ++s) {
    az[s] = s == kSingular ? same_az.data() : spread_az.data();
    el[s] = s == kSingular ? same_el.data() : spread_el.data();
    ys[s] = y.data();
  }
  Search search(gp);
  search.load(3, kLanes, az, el, ys);
  double length_scale[kLanes], nll[kLanes];
  std::fill_n(length_scale, kLanes, 0.5);
  search.negLogMarginalLikelihood(length_scale, nll);
  Search alone(gp);
  const float* one_az = spread_az.data();
  const float* one_el = spread_el.data();
  const double* one_y = y.data();
  alone.load(3, 1, &one_az, &one_el, &one_y);
  double alone_nll[kLanes];
  alone.negLogMarginalLikelihood(length_scale, alone_nll);
  ASSERT_TRUE(std::isfinite(alone_nll[0]));
  for (int s = 0; s < kLanes; ++s) {
    if (s == kSingular) {
      EXPECT_TRUE(std::isinf(nll[s]) && nll[s] > 0.0) << nll[s];
    } else {
      EXPECT_EQ(nll[s], alone_nll[0]) << s;
    }
  }
}

}  // namespace

TEST(LengthScaleSearch, SingularLaneIsInfiniteAndAloneDouble) {
  expectSingularLaneIsInfinite<mm::LengthScaleSearch>();
}

TEST(LengthScaleSearch, SingularLaneIsInfiniteAndAloneSingle) {
  expectSingularLaneIsInfinite<mm::SingleLengthScaleSearch>();
}
