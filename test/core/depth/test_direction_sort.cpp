#include "multimodal_nvs/core/depth/direction_sort.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace mm = multimodal_nvs;

namespace {

bool byDirectionThenDepth(const mm::AngularSample& a, const mm::AngularSample& b) {
  if (a.elevation_deg != b.elevation_deg) return a.elevation_deg < b.elevation_deg;
  if (a.azimuth_deg != b.azimuth_deg) return a.azimuth_deg < b.azimuth_deg;
  return a.depth < b.depth;
}

/// Equal when every sample has the same angles and depth as its counterpart; -0 and +0 compare
/// equal (the two orders may place them either way).
void expectSameOrder(const std::vector<mm::AngularSample>& got,
                     const std::vector<mm::AngularSample>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].elevation_deg, want[i].elevation_deg) << i;
    ASSERT_EQ(got[i].azimuth_deg, want[i].azimuth_deg) << i;
    ASSERT_EQ(got[i].depth, want[i].depth) << i;
  }
}

}  // namespace

TEST(DirectionSort, EqualsStdSortWithTheFloatComparison) {
  // LiDAR-like rings (many equal elevations), angles of both signs spanning wide and tiny
  // magnitudes (every radix digit matters), repeated directions with other depths, and -0 / +0.
  std::mt19937 random(17);
  std::uniform_real_distribution<float> azimuth(-60.0f, 60.0f), depth(0.5f, 80.0f);
  std::uniform_int_distribution<int> ring(0, 31);
  std::vector<mm::AngularSample> samples;
  for (int i = 0; i < 20000; ++i)
    samples.push_back({azimuth(random), -15.0f + 0.6f * ring(random), depth(random)});
  for (int i = 0; i < 500; ++i)
    samples.push_back({samples[i * 13].azimuth_deg, samples[i * 13].elevation_deg, depth(random)});
  for (float tiny : {1e-30f, -1e-30f, 1e-38f, -2e-38f, 3e-7f, -3e-7f})
    samples.push_back({tiny, -tiny, 5.0f});
  samples.push_back({0.0f, -0.0f, 4.0f});
  samples.push_back({-0.0f, 0.0f, 3.0f});
  samples.push_back({-0.0f, -0.0f, 6.0f});
  samples.push_back({1e30f, -1e30f, 2.0f});
  std::shuffle(samples.begin(), samples.end(), random);
  std::vector<mm::AngularSample> want = samples;
  std::sort(want.begin(), want.end(), byDirectionThenDepth);
  mm::sortByDirectionThenDepth(samples);
  expectSameOrder(samples, want);
}

TEST(DirectionSort, SmallAndOneValuedInputs) {
  std::vector<mm::AngularSample> none;
  mm::sortByDirectionThenDepth(none);
  EXPECT_TRUE(none.empty());
  std::vector<mm::AngularSample> one = {{1.0f, 2.0f, 3.0f}};
  mm::sortByDirectionThenDepth(one);
  EXPECT_EQ(one[0].depth, 3.0f);
  // One direction only: every radix pass is skipped, the depths still sorted.
  std::vector<mm::AngularSample> same = {
      {1.0f, 2.0f, 9.0f}, {1.0f, 2.0f, 3.0f}, {1.0f, 2.0f, 5.0f}};
  mm::sortByDirectionThenDepth(same);
  EXPECT_EQ(same[0].depth, 3.0f);
  EXPECT_EQ(same[1].depth, 5.0f);
  EXPECT_EQ(same[2].depth, 9.0f);
}
