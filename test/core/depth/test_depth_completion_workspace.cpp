// DepthCompletionWorkspace and its cost policies: the automatic point cap per model, the release
// of buffers an oversized scan left behind, and completion through the reused buffers.
#include <gtest/gtest.h>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/depth_completion_workspace.hpp"

namespace mm = multimodal_nvs;
using mm::test::planePoints;
using mm::test::smallCamera;
using mm::test::smallImage;

TEST(PointCap, NegativeIsUnlimitedPositiveIsTakenAsItIs) {
  const mm::DepthCompletionParams params;
  EXPECT_EQ(mm::pointCap(-1, params), 0u);
  EXPECT_EQ(mm::pointCap(123, params), 123u);
}

TEST(PointCap, AutomaticCapIsSmallOnlyForTheExactGp) {
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kLocalGpMle;
  EXPECT_EQ(mm::pointCap(0, params), 5000u);
  params.max_neighbors = 64;  // the tile approximation is linear in the points
  EXPECT_EQ(mm::pointCap(0, params), 200000u);
  for (auto model : {mm::DepthModel::kKernel, mm::DepthModel::kGroundGp}) {
    params.model = model;
    params.max_neighbors = 0;
    EXPECT_EQ(mm::pointCap(0, params), 200000u) << mm::toString(model);
  }
}

TEST(OversizedBuffers, OnlyBuffersFarLargerThanTheirContentsAreReleased) {
  std::vector<Eigen::Vector3d> points(200000);
  mm::DepthMap depth;
  depth.depth.resize(300000);
  depth.variance.resize(300000);
  depth.valid.resize(300000);
  mm::releaseOversizedBuffers(points, depth);  // full: kept
  EXPECT_EQ(points.capacity(), 200000u);
  EXPECT_EQ(depth.depth.capacity(), 300000u);

  points.resize(10);
  mm::releaseOversizedBuffers(points, depth);
  EXPECT_EQ(points.capacity(), 0u);
  EXPECT_EQ(depth.depth.capacity(), 300000u);

  depth.valid.resize(100);  // one oversized buffer releases the whole map
  mm::releaseOversizedBuffers(points, depth);
  EXPECT_EQ(depth.depth.capacity(), 0u);
  EXPECT_EQ(depth.variance.capacity(), 0u);
  EXPECT_EQ(depth.valid.capacity(), 0u);

  std::vector<float> small(10);
  small.reserve(4 * 10 + (1 << 16));  // within the slack
  EXPECT_FALSE(mm::oversized(small));
  small.reserve(4 * 10 + (1 << 16) + 1);
  EXPECT_TRUE(mm::oversized(small));
}

TEST(DepthCompletionWorkspace, MatchesTheCompleterScanAfterScan) {
  mm::DepthCompletionParams params;
  params.threads = 2;
  mm::DepthCompletionWorkspace workspace;
  for (double depth : {6.0, 9.0}) {
    const auto points = planePoints(smallCamera(), smallImage(), depth, 11);
    workspace.points() = points;
    const mm::DepthMap& got = workspace.complete(smallCamera(), {smallImage(), 2}, params);
    EXPECT_EQ(&got, &workspace.depth());
    const mm::DepthMap want =
        mm::DepthCompleter(2).complete(points, smallCamera(), {smallImage(), 2}, params);
    EXPECT_EQ(got.depth, want.depth);
    EXPECT_EQ(got.variance, want.variance);
    EXPECT_EQ(got.valid, want.valid);
    EXPECT_EQ(got.stats.kept, want.stats.kept);
  }
}

TEST(DepthCompletionWorkspace, ReleasesOversizedBuffersAlsoWhenTheCompletionThrows) {
  mm::DepthCompletionWorkspace workspace;
  workspace.points().reserve(1 << 20);
  mm::DepthCompletionParams params;
  params.radius_deg = -1.0;  // invalid
  EXPECT_THROW(workspace.complete(smallCamera(), {smallImage(), 1}, params), mm::InputError);
  EXPECT_EQ(workspace.points().capacity(), 0u);
}
