// The nearest-surface prior's colours: cell colours of the camera image, the weight of a return by
// the resemblance of its pixel to the pixel's, and the weighted order statistic that picks the
// prior's depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/surface_colours.hpp"

namespace mm = multimodal_nvs;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {
// The colours of an image of its own size (the depth grid's image in the models).
mm::SurfaceColours coloursOf(const cv::Mat& image, double sigma = 20.0) {
  return mm::SurfaceColours(image, mm::ImageSize{image.rows, image.cols}, sigma);
}
}  // namespace

TEST(WeightedOrderStatistic, EqualWeightsGiveThePlainOrderStatistic) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> depth(0.5f, 80.0f);
  for (int trial = 0; trial < 500; ++trial) {
    const std::size_t n = 1 + trial % 12 + (trial % 50 == 0 ? 70 : 0);  // a few beyond 64 values
    std::vector<float> d(n);
    for (float& x : d)
      x = trial % 5 == 0 ? std::round(depth(rng) / 20.0f) : depth(rng);  // ties too
    std::vector<float> sorted = d;
    std::sort(sorted.begin(), sorted.end());
    const std::vector<float> weights(n, 0.05f + float(trial % 7));
    for (std::size_t pick = 0; pick < n; ++pick) {
      const std::size_t at =
          mm::weightedOrderStatistic(d, weights, (double(pick) + 0.5) / double(n));
      ASSERT_LT(at, n);
      ASSERT_EQ(d[at], sorted[pick]) << "trial " << trial << " pick " << pick;
    }
  }
}

TEST(WeightedOrderStatistic, ALightNearValueIsPassedOver) {
  // The second smallest of four (fraction 1.5 / 4) by weight: the near value's small weight does
  // not reach it, so the next value stands.
  const std::vector<float> depths{30.0f, 5.0f, 32.0f, 31.0f};
  EXPECT_EQ(mm::weightedOrderStatistic(depths, {1.0f, 0.05f, 1.0f, 1.0f}, 1.5 / 4.0), 3u);    // 31
  EXPECT_EQ(mm::weightedOrderStatistic(depths, {0.05f, 1.0f, 0.05f, 0.05f}, 1.5 / 4.0), 1u);  // 5
}

TEST(SurfaceColours, CellsAverageTheImageAndWeightsFallWithTheColourDistance) {
  constexpr int kCell = mm::SurfaceColours::kCellPx;
  cv::Mat image(4 * kCell, 4 * kCell, CV_8UC3, cv::Scalar(200, 0, 0));  // blue
  image(cv::Rect(0, 0, kCell, kCell)).setTo(cv::Scalar(0, 0, 200));     // red top-left cell
  image.at<cv::Vec3b>(kCell, kCell) = cv::Vec3b(0, 200, 0);             // one green pixel
  const mm::SurfaceColours colours = coloursOf(image);
  const mm::CellColour red = colours.at(1.0, 2.0), blue = colours.at(3.5 * kCell, 3.5 * kCell);
  EXPECT_EQ(red, (mm::CellColour{0.0f, 0.0f, 200.0f}));
  EXPECT_EQ(blue, (mm::CellColour{200.0f, 0.0f, 0.0f}));
  // The green pixel is averaged into its cell, not read alone.
  const mm::CellColour mixed = colours.at(kCell + 0.5, kCell + 0.5);
  // (8-bit averaging rounds to whole values)
  EXPECT_NEAR(mixed[0], 200.0f * (kCell * kCell - 1) / (kCell * kCell), 0.51f);
  EXPECT_NEAR(mixed[1], 200.0f / (kCell * kCell), 0.51f);
  EXPECT_TRUE(std::isnan(colours.at(-0.5, 1.0)[0]));
  EXPECT_TRUE(std::isnan(colours.at(1.0, 4.0 * kCell)[0]));
  EXPECT_FLOAT_EQ(colours.weight(blue, blue), 1.0f);
  EXPECT_NEAR(colours.weight(red, blue), mm::SurfaceColours::kWeightFloor, 1e-6f);
  // sigma 20: exp(-1/2) of the span above the floor at a distance of 20.
  const mm::CellColour near_blue{180.0f, 0.0f, 0.0f};
  EXPECT_NEAR(colours.weight(blue, near_blue),
              mm::SurfaceColours::kWeightFloor +
                  (1.0f - mm::SurfaceColours::kWeightFloor) * std::exp(-0.5f),
              1e-5f);
  EXPECT_FLOAT_EQ(colours.weight(blue, near_blue), colours.weight(near_blue, blue));
  // Unknown colours (outside the image) weigh as much as a match: no evidence either way.
  EXPECT_FLOAT_EQ(colours.weight(colours.at(-1.0, -1.0), red), 1.0f);
}

TEST(SurfaceColours, GrayAndSixteenBitImagesReadAsTheirColourAndOthersAreRefused) {
  const cv::Mat gray(16, 16, CV_8UC1, cv::Scalar(90));
  EXPECT_EQ(coloursOf(gray).at(3.0, 3.0), (mm::CellColour{90.0f, 90.0f, 90.0f}));
  const cv::Mat deep(16, 16, CV_16UC3, cv::Scalar(256 * 10, 256 * 20, 256 * 30));
  EXPECT_EQ(coloursOf(deep).at(3.0, 3.0), (mm::CellColour{10.0f, 20.0f, 30.0f}));
  EXPECT_THROW(coloursOf(cv::Mat(16, 16, CV_32FC3)), mm::InputError);
  EXPECT_THROW(coloursOf(cv::Mat(16, 16, CV_8UC2)), mm::InputError);
  // An image of another size than the depth grid's is refused, not read at the wrong pixels.
  EXPECT_THROW(mm::SurfaceColours(gray, mm::ImageSize{16, 32}, 20.0), mm::InputError);
  EXPECT_THROW(mm::SurfaceColours(cv::Mat(), mm::ImageSize{16, 16}, 20.0), mm::InputError);
}

TEST(SurfaceColours, SamplesReadTheCellOfTheirPixel) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar(200, 0, 0));
  image.rowRange(60, smallImage().height).setTo(cv::Scalar(0, 0, 200));
  const mm::SurfaceColours colours = coloursOf(image);
  const auto samples = mm::toAngularSamples(
      {pointOnPixelRay(smallCamera(), 30, 20, 8.0), pointOnPixelRay(smallCamera(), 100, 90, 4.0)});
  const std::vector<mm::CellColour> at = colours.atSamples(samples, angles);
  ASSERT_EQ(at.size(), 2u);
  EXPECT_EQ(at[0], (mm::CellColour{200.0f, 0.0f, 0.0f}));
  EXPECT_EQ(at[1], (mm::CellColour{0.0f, 0.0f, 200.0f}));
}

// The facade above a parked car: the car's near return is among the facade pixel's nearest, and
// the plain minimum takes its depth; weighed by colour, the facade's own returns decide there,
// while on the car the car's return still does.
TEST(SurfaceColours, TheNearestSurfacePriorTakesTheReturnsThatLookLikeThePixel) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar(200, 120, 40));
  image.rowRange(64, smallImage().height).setTo(cv::Scalar(30, 30, 180));  // the car below
  const auto samples = mm::toAngularSamples(
      {pointOnPixelRay(smallCamera(), 80, 68, 5.0), pointOnPixelRay(smallCamera(), 81, 56, 30.0),
       pointOnPixelRay(smallCamera(), 79, 55, 31.0), pointOnPixelRay(smallCamera(), 80, 54, 32.0)});
  const mm::SurfaceColours colours = coloursOf(image);
  const auto plain = mm::nearestSurfaceRows(samples, angles, 4, 1, 1, pool);
  const auto weighed = mm::nearestSurfaceRows(samples, angles, 4, 1, 1, pool, nullptr,
                                              mm::SurfacePriorImage{&colours});
  EXPECT_NEAR(plain.depth(60, 80), 5.0f, 1e-4f);     // the facade pixel takes the car's depth
  EXPECT_NEAR(weighed.depth(60, 80), 30.0f, 1e-3f);  // ... unless the colours weigh in
  EXPECT_NEAR(weighed.depth(70, 80), 5.0f, 1e-4f);   // the car keeps its own
  // A uniform image weighs every return alike: the plain prior, bit for bit.
  const mm::SurfaceColours uniform =
      coloursOf(cv::Mat(image.size(), CV_8UC3, cv::Scalar::all(128)));
  const auto same = mm::nearestSurfaceRows(samples, angles, 4, 2, 3, pool, nullptr,
                                           mm::SurfacePriorImage{&uniform});
  const auto rank2 = mm::nearestSurfaceRows(samples, angles, 4, 2, 3, pool);
  EXPECT_EQ(same.depth_rows, rank2.depth_rows);
  EXPECT_EQ(same.distance_rows, rank2.distance_rows);
}

// More returns than the brute-force search takes (the binned search's path): the same weighing.
TEST(SurfaceColours, ManyReturnsAreWeighedAsAFew) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 159.0), v(0.0, 119.0), z(2.0, 60.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 5000; ++i)
    points.push_back(pointOnPixelRay(smallCamera(), u(rng), v(rng), z(rng)));
  const auto samples = mm::toAngularSamples(points);
  const mm::SurfaceColours uniform =
      coloursOf(cv::Mat(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(128)));
  const auto same = mm::nearestSurfaceRows(samples, angles, 8, 2, 4, pool, nullptr,
                                           mm::SurfacePriorImage{&uniform});
  const auto plain = mm::nearestSurfaceRows(samples, angles, 8, 2, 4, pool);
  EXPECT_EQ(same.depth_rows, plain.depth_rows);
  // A striped image: the weighed prior differs from the plain one somewhere, and is one of the
  // returns' depths at every lattice node (a pick, not a blend).
  cv::Mat stripes(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar(200, 120, 40));
  for (int r = 0; r < stripes.rows; r += 8)
    stripes.rowRange(r, std::min(r + 4, stripes.rows)).setTo(cv::Scalar(30, 30, 180));
  const mm::SurfaceColours striped = coloursOf(stripes);
  const auto weighed = mm::nearestSurfaceRows(samples, angles, 8, 2, 4, pool, nullptr,
                                              mm::SurfacePriorImage{&striped});
  EXPECT_NE(weighed.depth_rows, plain.depth_rows);
  std::vector<float> depths;
  for (const auto& s : samples)
    depths.push_back(s.depth);
  std::sort(depths.begin(), depths.end());
  for (std::size_t i = 0; i < weighed.node_rows.size(); ++i) {
    for (int c = 0; c < angles.grid().cols(); c += 4) {
      const float d = weighed.depth_rows[i * angles.grid().cols() + c];
      ASSERT_TRUE(std::binary_search(depths.begin(), depths.end(), d)) << i << " " << c;
    }
  }
}

// ground_gp alone with the colours on: an image of another size than the depth grid's is an
// InputError (as for the sky and image_guided), the right one completes.
TEST(SurfaceColours, GroundGpRefusesAMisSizedImage) {
  mm::DepthCompletionParams p;
  p.model = mm::DepthModel::kGroundGp;
  p.ground.input = mm::GroundPriorParams::Input::kSparse;
  p.ground.surface_colour_sigma = 20.0;
  const std::vector<Eigen::Vector3d> returns = {pointOnPixelRay(smallCamera(), 40, 50, 8.0),
                                                pointOnPixelRay(smallCamera(), 120, 45, 20.0),
                                                pointOnPixelRay(smallCamera(), 80, 30, 30.0)};
  mm::DepthCompleter completer(2);
  const cv::Mat small(smallImage().height / 2, smallImage().width / 2, CV_8UC3,
                      cv::Scalar::all(90));
  EXPECT_THROW(completer.complete(returns, smallCamera(), {smallImage(), 1}, p, small),
               mm::InputError);
  const cv::Mat right(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(90));
  const mm::DepthMap map = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, right);
  EXPECT_EQ(map.depth.size(), std::size_t(smallImage().height) * smallImage().width);
}

TEST(SurfacePriorWalls, AReturnContinuesAsAWallOnlyTowardsTheImageCentre) {
  // A facade return 0.4 right of the axis (normalised x) at 10 m: X = 4 m.
  EXPECT_DOUBLE_EQ(mm::wallDepth(0.4, 10.0, 0.2, 100.0), 20.0);
  EXPECT_DOUBLE_EQ(mm::wallDepth(-0.4, 10.0, -0.1, 100.0), 40.0);
  EXPECT_DOUBLE_EQ(mm::wallDepth(0.4, 10.0, 0.5, 100.0), 10.0);    // beyond the return
  EXPECT_DOUBLE_EQ(mm::wallDepth(0.4, 10.0, -0.2, 100.0), 10.0);   // the other side
  EXPECT_DOUBLE_EQ(mm::wallDepth(0.4, 10.0, 0.0, 100.0), 10.0);    // on the axis
  EXPECT_DOUBLE_EQ(mm::wallDepth(0.4, 10.0, 0.01, 100.0), 100.0);  // capped
  EXPECT_DOUBLE_EQ(mm::wallDepth(0.4, 150.0, 0.2, 100.0), 150.0);  // never nearer than the return
  // The back of a vehicle ahead (near the axis) is not a wall.
  EXPECT_DOUBLE_EQ(mm::wallDepth(0.5 * mm::kWallMinOffAxis, 10.0, 0.01, 100.0), 10.0);
}

// A facade along the right of the street, seen at one return: the pixels of its colour between
// the return and the image centre take the wall's depth; a pixel of another colour there, or
// without walls, the return's own.
TEST(SurfacePriorWalls, TheNearestSurfacePriorContinuesALookAlikeReturnAsAWall) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar(150, 190, 200));
  image.rowRange(80, smallImage().height).setTo(cv::Scalar(40, 40, 40));  // the road, dark
  const auto samples = mm::toAngularSamples({pointOnPixelRay(smallCamera(), 140, 40, 10.0)});
  const mm::SurfaceColours colours = coloursOf(image);
  const mm::SurfacePriorImage walls{&colours, true, 100.0};
  const auto with = mm::nearestSurfaceRows(samples, angles, 1, 1, 1, pool, nullptr, walls);
  const auto without = mm::nearestSurfaceRows(samples, angles, 1, 1, 1, pool, nullptr,
                                              mm::SurfacePriorImage{&colours});
  // Column 110 of row 40: normalised x 0.3 against the return's 0.6, X = 6 m: a wall at 20 m.
  EXPECT_NEAR(with.depth(40, 110), 20.0f, 1e-3f);
  EXPECT_NEAR(without.depth(40, 110), 10.0f, 1e-4f);
  EXPECT_NEAR(with.depth(40, 150), 10.0f, 1e-4f);   // beyond the return: its own depth
  EXPECT_NEAR(with.depth(100, 110), 10.0f, 1e-4f);  // the road's colour: no wall
}
