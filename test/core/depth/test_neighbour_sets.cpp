// Neighbour sets and set sharing: the segment/dedup structure must give every pixel exactly the
// neighbours of the brute-force float32 test, and the shared per-set solution must equal a
// per-pixel computation.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/depth_shift.hpp"
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"
#include "multimodal_nvs/core/depth/gp/local_gp.hpp"
#include "multimodal_nvs/core/depth/gp/reference_arithmetic.hpp"
#include "multimodal_nvs/core/depth/models/local_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/neighbour_sets.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace mm = multimodal_nvs;

namespace {

std::vector<mm::AngularSample> randomSamples(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 160), v(0, 120), z(2, 40);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    points.push_back(mm::test::pointOnPixelRay(mm::test::smallCamera(), u(rng), v(rng), z(rng)));
  }
  points.push_back(points[3]);  // a duplicate
  return mm::toAngularSamples(points);
}

std::vector<int> bruteForceNeighbours(const std::vector<mm::AngularSample>& samples, float az,
                                      float el, float radius_sq) {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(samples.size()); ++i) {
    if (mm::withinRadius(az, el, samples[i].azimuth_deg, samples[i].elevation_deg, radius_sq)) {
      out.push_back(i);
    }
  }
  return out;
}

}  // namespace

TEST(NeighbourSets, EveryPixelSeesExactlyTheBruteForceNeighbours) {
  const auto samples = randomSamples(60, 7);
  struct Case {
    mm::ImageSize image;
    int stride;
    float radius;
  };
  // Narrow windows (a few columns), windows of more than 64 and 128 columns clipped at the image's
  // sides, and windows of exactly 128 columns with runs up to their end.
  const std::vector<Case> cases = {{mm::test::smallImage(), 1, 4.0f},
                                   {mm::test::smallImage(), 3, 4.0f},
                                   {mm::test::smallImage(), 1, 45.0f},
                                   {{40, 128}, 1, 80.0f},
                                   {{30, 192}, 1, 25.0f}};
  for (const Case& test_case : cases) {
    const int stride = test_case.stride;
    const float radius = test_case.radius;
    const mm::PixelAngleGrid grid(mm::test::smallCamera(), {test_case.image, stride});
    mm::ThreadPool pool(2);
    const auto sets = mm::NeighbourSets::build(samples, grid, radius, pool);
    std::vector<int> set_of(grid.grid().size(), -1);
    for (const auto& seg : sets.segments()) {
      for (int c = seg.col_begin; c < seg.col_end; ++c) {
        set_of[std::size_t(seg.row) * grid.grid().cols() + c] = seg.set_id;
      }
    }
    for (int r = 0; r < grid.grid().rows(); ++r) {
      for (int c = 0; c < grid.grid().cols(); ++c) {
        const auto expected = bruteForceNeighbours(samples, grid.azimuthRow(r)[c],
                                                   grid.elevationRow(r)[c], radius * radius);
        const int id = set_of[std::size_t(r) * grid.grid().cols() + c];
        std::vector<int> got;
        if (id >= 0) got.assign(sets.members(id), sets.members(id) + sets.setSize(id));
        ASSERT_EQ(got, expected) << "pixel " << r << "," << c << " radius " << radius;
      }
    }
    // Sets are distinct: deduplication worked.
    std::vector<std::vector<int>> all;
    for (int s = 0; s < sets.setCount(); ++s)
      all.emplace_back(sets.members(s), sets.members(s) + sets.setSize(s));
    std::sort(all.begin(), all.end());
    EXPECT_EQ(std::adjacent_find(all.begin(), all.end()), all.end());
  }
}

// Samples left of and below the optical axis have negative bins. Their keys were once formed by
// left-shifting a negative int64 (undefined behaviour before C++20, reported by UBSan in the
// sanitizer build of `make test`); the order must stay lexicographic in (azimuth bin, elevation
// bin) across the sign change.
TEST(NeighbourSets, SampleRanksOrderNegativeBinsBeforePositiveOnes) {
  const std::vector<mm::AngularSample> samples = {
      {5.5f, -3.5f, 10.0f}, {-7.5f, 2.5f, 10.0f}, {5.5f, 2.5f, 10.0f}, {-7.5f, -3.5f, 10.0f}};
  const auto rank = mm::referenceSampleRanks(samples, 2.0);
  // (bx, by): (2, -2), (-4, 1), (2, 1), (-4, -2).
  EXPECT_LT(rank[3], rank[1]);
  EXPECT_LT(rank[1], rank[0]);
  EXPECT_LT(rank[0], rank[2]);
}

TEST(NeighbourSets, SharedSolutionEqualsPerPixelComputation) {
  const auto samples = randomSamples(40, 11);
  const mm::PixelAngleGrid grid(mm::test::smallCamera(), {mm::test::smallImage(), 2});
  mm::DepthCompletionParams params;
  params.radius_deg = 4.0;
  mm::ThreadPool pool(2);
  const auto sets = mm::NeighbourSets::build(samples, grid, 4.0f, pool);
  const double shift = mm::computeShift(params.shift, samples);
  mm::PixelPredictions shared;
  mm::predictLocalGp(samples, grid, sets, params, shift, pool, shared);
  const auto targets = mm::shiftedTargets(samples, shift);
  const auto rank = mm::referenceSampleRanks(samples, params.radius_deg);

  mm::LocalGp gp(params.gp);
  int checked = 0;
  for (int r = 0; r < grid.grid().rows(); r += 3) {
    for (int c = 0; c < grid.grid().cols(); c += 3) {
      const float paz = grid.azimuthRow(r)[c], pel = grid.elevationRow(r)[c];
      const auto members = bruteForceNeighbours(samples, paz, pel, 16.0f);
      const std::size_t pixel = std::size_t(r) * grid.grid().cols() + c;
      if (members.empty()) {
        ASSERT_EQ(shared.variance[pixel], 625.0f);
        continue;
      }
      std::vector<float> az, el;
      std::vector<double> y;
      for (int m : members) {
        az.push_back(samples[m].azimuth_deg);
        el.push_back(samples[m].elevation_deg);
        y.push_back(targets[m]);
      }
      const int n = static_cast<int>(members.size());
      gp.setData(az.data(), el.data(), y.data(), n);
      double l;
      if (n == 2) {
        const int a = rank[members[0]] <= rank[members[1]] ? 0 : 1, b = 1 - a;
        l = mm::goldenSectionMinimize(
            [&](double ls) {
              return mm::referenceNllTwoSamples(az[a], el[a], y[a], az[b], el[b], y[b], 25, 0.5,
                                                ls);
            },
            0.1, 10.0, 1e-3, 64);
      } else {
        l = gp.searchLengthScale();
      }
      std::vector<double> factor, beta;
      ASSERT_TRUE(gp.posterior(l, factor, beta));
      float mean, var;
      mm::predictFromFactor(factor.data(), beta.data(), az.data(), el.data(), n, l, params.gp, &paz,
                            &pel, 1, shift, &mean, &var);
      ASSERT_NEAR(shared.mean[pixel], mean, 1e-4) << r << "," << c;
      ASSERT_NEAR(shared.variance[pixel], var, 1e-3) << r << "," << c;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(ReferenceArithmetic, ArgsortMatchesNumpyIncludingTheOrderOfTies) {
  // np.argsort of this array (numpy 1.24, default kind) printed by /usr/bin/python3.
  const std::vector<std::int64_t> keys{5, 3, 5, 1, 3, 3, 5, 0, 2, 5, 5, 1, 3, 7, 7, 7, 5, 5, 3, 2,
                                       1, 0, 5, 5, 5, 3, 3, 1, 2, 9, 5, 5, 4, 4, 4, 5, 3, 3, 5, 1};
  const std::vector<int> expected{21, 7,  39, 27, 3, 20, 11, 28, 19, 8,  26, 37, 36, 12,
                                  25, 18, 5,  4,  1, 34, 33, 32, 2,  9,  35, 30, 31, 24,
                                  22, 38, 17, 16, 6, 10, 23, 0,  15, 14, 13, 29};
  EXPECT_EQ(mm::numpyArgsortQuicksort(keys), expected);
}

TEST(ReferenceArithmetic, TwoSampleLikelihoodAgreesWithTheGenericOne) {
  const float az[2] = {1.25f, 2.5f}, el[2] = {-0.75f, 0.5f};
  const double y[2] = {3.5, -7.25};
  mm::LocalGp gp({});
  gp.setData(az, el, y, 2);
  for (double l : {0.1, 0.37, 1.0, 2.2, 9.9}) {
    const double generic = gp.negLogMarginalLikelihood(l);
    const double exact =
        mm::referenceNllTwoSamples(az[0], el[0], y[0], az[1], el[1], y[1], 25, 0.5, l);
    EXPECT_NEAR(generic, exact, 1e-9 * std::abs(generic)) << l;
  }
}

TEST(LocalGp, GoldenSectionFindsTheMinimumOfAParabola) {
  const double l = mm::goldenSectionMinimize([](double x) { return (x - 3.3) * (x - 3.3); }, 0.1,
                                             10.0, 1e-3, 64);
  EXPECT_NEAR(l, 3.3, 1e-3);
}

TEST(LocalGp, PackedCholeskyRejectsIndefiniteMatrices) {
  double indefinite[3] = {1.0, 2.0, 1.0};  // [[1, 2], [2, 1]]
  EXPECT_FALSE(mm::choleskyPacked(indefinite, 2));
  double spd[3] = {4.0, 2.0, 5.0};  // [[4, 2], [2, 5]] -> L = [[2, 0], [1, 2]]
  ASSERT_TRUE(mm::choleskyPacked(spd, 2));
  EXPECT_DOUBLE_EQ(spd[0], 2.0);
  EXPECT_DOUBLE_EQ(spd[1], 1.0);
  EXPECT_DOUBLE_EQ(spd[2], 2.0);
}
