// The enclosed-surface rule of the nearest-surface prior: a node that looks like none of its
// returns, enclosed by nodes that look like theirs, takes the nearest of theirs.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <vector>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/enclosed_surfaces.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/surface_colours.hpp"

namespace mm = multimodal_nvs;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {
// A rows x cols lattice of look-alike returns `label` everywhere but the nodes listed (-1).
std::vector<int> lattice(int rows, int cols, int label,
                         const std::vector<std::pair<int, int>>& open) {
  std::vector<int> l(std::size_t(rows) * cols, label);
  for (const auto& [r, c] : open)
    l[std::size_t(r) * cols + c] = -1;
  return l;
}
}  // namespace

TEST(EnclosedSurfaces, AWindowInsideAFacadeTakesTheFacadesReturn) {
  const std::vector<int> l = lattice(5, 5, 7, {{2, 2}, {2, 3}});
  const std::vector<int> e = mm::enclosingLookAlikes(l, 5, 5, 2);
  EXPECT_EQ(e[2 * 5 + 2], 7);
  EXPECT_EQ(e[2 * 5 + 3], 7);
  // Nodes with their own look-alike are left alone.
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (i != 2 * 5 + 2 && i != 2 * 5 + 3) {
      EXPECT_EQ(e[i], -1) << i;
    }
  }
}

TEST(EnclosedSurfaces, ThreeSidesEncloseTwoDoNot) {
  // Node (1, 1) of a 3x3 lattice whose bottom row and right column have no look-alike: open below
  // and to the right (two sides) -> not enclosed. With the right column closed: three sides.
  std::vector<int> l = lattice(3, 3, 4, {{1, 1}, {2, 0}, {2, 1}, {2, 2}, {0, 2}, {1, 2}});
  EXPECT_EQ(mm::enclosingLookAlikes(l, 3, 3, 2)[1 * 3 + 1], -1);
  l = lattice(3, 3, 4, {{1, 1}, {2, 0}, {2, 1}, {2, 2}});
  EXPECT_EQ(mm::enclosingLookAlikes(l, 3, 3, 2)[1 * 3 + 1], 4);
  static_assert(mm::kEnclosingSides == 3, "the test's cases assume three sides");
}

TEST(EnclosedSurfaces, OnlyLookAlikesWithinTheRadiusCountAndTheNearestWins) {
  // Row 0 of a 1-row lattice can only see left and right: never three sides.
  EXPECT_EQ(mm::enclosingLookAlikes({1, -1, 2}, 1, 3, 5)[1], -1);
  // A 7x7 lattice, all open but a cross of look-alikes around the centre (3, 3): left at 1 node
  // (label 1), right at 2 (label 2), above at 3 (label 3), below none.
  std::vector<int> l(49, -1);
  l[3 * 7 + 2] = 1;
  l[3 * 7 + 5] = 2;
  l[0 * 7 + 3] = 3;
  EXPECT_EQ(mm::enclosingLookAlikes(l, 7, 7, 3)[3 * 7 + 3], 1);   // three sides, left nearest
  EXPECT_EQ(mm::enclosingLookAlikes(l, 7, 7, 2)[3 * 7 + 3], -1);  // above is 3 nodes away
  // Left and right at the same distance: the first side in the order left, right, above, below.
  l[3 * 7 + 2] = -1;
  l[3 * 7 + 1] = 1;
  EXPECT_EQ(mm::enclosingLookAlikes(l, 7, 7, 3)[3 * 7 + 3], 1);
}

TEST(EnclosedSurfaces, BadInputGivesNoFill) {
  EXPECT_EQ(mm::enclosingLookAlikes({-1, 1, 1}, 2, 2, 2), std::vector<int>(3, -1));  // size
  EXPECT_EQ(mm::enclosingLookAlikes(lattice(3, 3, 1, {{1, 1}}), 3, 3, 0), std::vector<int>(9, -1));
}

TEST(EnclosedSurfaces, TheRadiusIsAnAngleAtTheLatticesSpacing) {
  // 16 px at f = 748 px (the synthetic scenes) is 1.225 degrees: 10 degrees are 8 nodes; at VoD's
  // f = 1495 px 16 of them.
  EXPECT_EQ(mm::nodesWithin(10.0, 16.0, 748.0), 8);
  EXPECT_EQ(mm::nodesWithin(10.0, 16.0, 1495.0), 16);
  EXPECT_EQ(mm::nodesWithin(0.0, 16.0, 748.0), 0);
  EXPECT_EQ(mm::nodesWithin(10.0, 0.0, 748.0), 0);
  EXPECT_EQ(mm::nodesWithin(0.5, 16.0, 748.0), 0);  // less than one node
}

// A facade (one return, its colour) with a window of another colour in it, and a red car below
// with a nearer return. Without the rule the window's nodes, which look like neither return, take
// the nearer (the car's); with it, the facade's wall.
TEST(EnclosedSurfaces, TheNearestSurfacePriorGivesAWindowItsFacadesWall) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar(150, 190, 200));
  image.rowRange(80, smallImage().height).setTo(cv::Scalar(40, 40, 40));  // the road
  image(cv::Rect(90, 80, 40, 20)).setTo(cv::Scalar(30, 30, 200));         // the car
  image(cv::Rect(100, 20, 16, 16)).setTo(cv::Scalar(20, 120, 20));        // the window
  const auto samples = mm::toAngularSamples({pointOnPixelRay(smallCamera(), 140, 40, 10.0),
                                             pointOnPixelRay(smallCamera(), 110, 90, 6.0)});
  const mm::SurfaceColours colours(image, smallImage(), 20.0);
  mm::SurfacePriorImage prior{&colours, true, 100.0};
  const auto open = mm::nearestSurfaceRows(samples, angles, 2, 1, 1, pool, nullptr, prior);
  prior.fill_deg = 20.0;
  const auto filled = mm::nearestSurfaceRows(samples, angles, 2, 1, 1, pool, nullptr, prior);
  // The window's centre, column 108: normalised x 0.28 against the facade return's 0.6 (X = 6 m).
  EXPECT_NEAR(open.depth(28, 108), 6.0f, 1e-4f);
  EXPECT_NEAR(filled.depth(28, 108), 6.0 / 0.28, 1e-3);
  // The facade around it is the wall either way, and the car its own return's.
  EXPECT_NEAR(open.depth(50, 108), 6.0 / 0.28, 1e-3);
  EXPECT_NEAR(filled.depth(50, 108), 6.0 / 0.28, 1e-3);
  EXPECT_NEAR(filled.depth(90, 125), 6.0f, 1e-4f);
}
