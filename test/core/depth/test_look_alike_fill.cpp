// The nearest-surface prior's fill: a node that looks like none of its returns takes the
// look-alike return of the nearest node along its row or column that found one.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/look_alike_fill.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/surface_colours.hpp"

namespace mm = multimodal_nvs;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {
// A rows x cols lattice of look-alike return `label` everywhere but the nodes listed (-1).
std::vector<int> lattice(int rows, int cols, int label,
                         const std::vector<std::pair<int, int>>& open) {
  std::vector<int> l(std::size_t(rows) * cols, label);
  for (const auto& [r, c] : open)
    l[std::size_t(r) * cols + c] = -1;
  return l;
}
}  // namespace

TEST(LookAlikeFill, AWindowInsideAFacadeTakesTheFacadesReturn) {
  const std::vector<int> l = lattice(5, 5, 7, {{2, 2}, {2, 3}});
  const std::vector<int> e = mm::nearestLookAlikes(l, 5, 5, 2);
  EXPECT_EQ(e[2 * 5 + 2], 7);
  EXPECT_EQ(e[2 * 5 + 3], 7);
  // Nodes with their own look-alike are left alone.
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (i != 2 * 5 + 2 && i != 2 * 5 + 3) {
      EXPECT_EQ(e[i], -1) << i;
    }
  }
}

TEST(LookAlikeFill, TheNearestAlongTheRowOrColumnWithinTheRadiusWins) {
  // A 7x7 lattice, all without look-alikes but three around the centre (3, 3): left at 2 nodes
  // (label 1), right at 1 (label 2), above at 3 (label 3).
  std::vector<int> l(49, -1);
  l[3 * 7 + 1] = 1;
  l[3 * 7 + 4] = 2;
  l[0 * 7 + 3] = 3;
  EXPECT_EQ(mm::nearestLookAlikes(l, 7, 7, 3)[3 * 7 + 3], 2);
  // Only the one above within reach of (6, 3)? It is 6 nodes up: beyond a radius of 3.
  EXPECT_EQ(mm::nearestLookAlikes(l, 7, 7, 3)[6 * 7 + 3], -1);
  EXPECT_EQ(mm::nearestLookAlikes(l, 7, 7, 6)[6 * 7 + 3], 3);
  // A diagonal neighbour does not count: label 1 at (3, 1) is in neither row 2 nor column 2.
  EXPECT_EQ(mm::nearestLookAlikes(l, 7, 7, 1)[2 * 7 + 2], -1);
  // Equal distances: the first side in the order left, right, above, below.
  l[3 * 7 + 4] = -1;
  l[3 * 7 + 5] = 2;
  EXPECT_EQ(mm::nearestLookAlikes(l, 7, 7, 3)[3 * 7 + 3], 1);
  // A filled node passes nothing on: (3, 2) takes label 1 at 1 node, but (3, 3) gets nothing
  // within 1 node from it.
  EXPECT_EQ(mm::nearestLookAlikes(l, 7, 7, 1)[3 * 7 + 3], -1);
}

TEST(LookAlikeFill, BadInputGivesNoFill) {
  EXPECT_EQ(mm::nearestLookAlikes({-1, 1, 1}, 2, 2, 2), std::vector<int>(3, -1));  // size
  EXPECT_EQ(mm::nearestLookAlikes(lattice(3, 3, 1, {{1, 1}}), 3, 3, 0),
            std::vector<int>(9, -1));  // radius
  EXPECT_TRUE(mm::nearestLookAlikes({}, 0, 0, 2).empty());
}

TEST(LookAlikeFill, TheRadiusIsAnAngleAtTheLatticesSpacing) {
  // 16 px at f = 748 px (the synthetic scenes) is 1.225 degrees: 10 degrees are 8 nodes; at VoD's
  // f = 1495 px 16 of them.
  EXPECT_EQ(mm::nodesWithin(10.0, 16.0, 748.0), 8);
  EXPECT_EQ(mm::nodesWithin(10.0, 16.0, 1495.0), 16);
  EXPECT_EQ(mm::nodesWithin(0.0, 16.0, 748.0), 0);
  EXPECT_EQ(mm::nodesWithin(10.0, 0.0, 748.0), 0);
  EXPECT_EQ(mm::nodesWithin(0.5, 16.0, 748.0), 0);  // less than one node
}

// A facade (one return, its colour) with a window of another colour in it, and a red car below
// with a nearer return. Without the fill the window's nodes, which look like neither return, take
// the nearer (the car's); with it, the facade's wall.
TEST(LookAlikeFill, TheNearestSurfacePriorGivesAWindowItsFacadesWall) {
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
  // Without colours there is nothing to fill from: the fill changes nothing.
  const mm::SurfacePriorImage plain{nullptr, true, 100.0, 20.0};
  EXPECT_EQ(mm::nearestSurfaceRows(samples, angles, 2, 1, 1, pool, nullptr, plain).depth_rows,
            mm::nearestSurfaceRows(samples, angles, 2, 1, 1, pool).depth_rows);
}

// Both parameters are angles in [0, 90] degrees; anything else (negative, beyond, NaN, infinite)
// is an InputError naming the parameter, before any work.
TEST(LookAlikeFill, AnglesOutsideZeroToNinetyDegreesAreRejected) {
  mm::DepthCompletionParams guided;
  guided.model = mm::DepthModel::kImageGuided;
  mm::DepthCompletionParams ground;
  ground.model = mm::DepthModel::kGroundGp;
  EXPECT_NO_THROW(guided.validate());
  EXPECT_NO_THROW(ground.validate());
  for (const double bad : {-1.0, 90.5, double(NAN), double(INFINITY)}) {
    mm::DepthCompletionParams p = guided;
    p.guided.prior_colour_fill_deg = bad;
    EXPECT_THROW(p.validate(), mm::InputError) << bad;
    p = ground;
    p.ground.surface_colour_fill_deg = bad;
    EXPECT_THROW(p.validate(), mm::InputError) << bad;
  }
  guided.guided.prior_colour_fill_deg = 90.0;
  ground.ground.surface_colour_fill_deg = 0.0;
  EXPECT_NO_THROW(guided.validate());
  EXPECT_NO_THROW(ground.validate());
}
