// The image_guided model: depth follows the returns but changes only at the image's edges, the sky
// goes to the far clamp, the variance grows away from the returns, and a missing image is an error.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <tuple>
#include <vector>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/models/image_guided_model.hpp"
#include "multimodal_nvs/core/depth/return_density.hpp"
#include "multimodal_nvs/core/depth/surface_colours.hpp"

namespace mm = multimodal_nvs;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {
constexpr int kCols = 160;

/// The model's defaults on its own ground and nearest-surface prior (on these few returns it would
/// otherwise stand on ground_gp's prediction; that prior has its own tests below); the tests of the
/// edges and the variance switch the lateral prior off, so that every pixel of a half starts from
/// the same prior (its own test is below).
mm::DepthCompletionParams guidedParams(bool lateral_prior = false) {
  mm::DepthCompletionParams p;
  p.model = mm::DepthModel::kImageGuided;
  p.threads = 2;
  p.guided.lateral_prior = lateral_prior;
  p.guided.ground_gp_prior = false;
  return p;
}

/// Left half dark, right half bright: one edge at column 80.
cv::Mat twoHalves() {
  cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(40));
  image.colRange(80, kCols).setTo(cv::Scalar::all(200));
  return image;
}

/// A near return on the dark half, a far one on the bright half, both below the horizon.
std::vector<Eigen::Vector3d> twoReturns() {
  return {pointOnPixelRay(smallCamera(), 60, 80, 5.0),
          pointOnPixelRay(smallCamera(), 100, 80, 20.0)};
}

float at(const mm::DepthMap& map, int row, int col) {
  return map.depth[std::size_t(row) * kCols + col];
}

/// The edge tests' setting: no ground plane and no sky, so that only the returns and the image
/// shape the depth.
mm::DepthCompletionParams edgeParams() {
  mm::DepthCompletionParams p = guidedParams();
  p.guided.ground_prior = false;
  p.guided.sky = false;
  return p;
}

/// The two returns over the two halves.
mm::DepthMap twoHalvesDepth(mm::DepthCompleter& completer, const mm::DepthCompletionParams& p) {
  return completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, p, twoHalves());
}
}  // namespace

TEST(ImageGuided, DepthChangesAtTheImageEdgeAndNotElsewhere) {
  mm::DepthCompletionParams p = edgeParams();
  mm::DepthCompleter completer(2);
  const auto map = twoHalvesDepth(completer, p);
  // Each return colours its own half up to the edge.
  EXPECT_NEAR(at(map, 80, 78), 5.0f, 0.5f);
  EXPECT_NEAR(at(map, 80, 82), 20.0f, 2.0f);
  // Without the image (the ablation), the two depths blur into each other across column 80.
  p.guided.edges = false;
  const auto blurred = twoHalvesDepth(completer, p);
  EXPECT_GT(std::abs(at(map, 80, 82) - at(map, 80, 78)),
            2.0f * std::abs(at(blurred, 80, 82) - at(blurred, 80, 78)));
}

// One return on a left wall (X = -4 m) above the horizon, and a smoother too weak to move evidence
// (lambda ~0), so each pixel shows its prior. Towards the image centre the wall continues along the
// view: its depth there is X / x (x = -0.2 at column 60: 20 m), not the return's 6.7 m. Outwards
// and on the other side of the centre the nearest return's own depth stays the prior.
TEST(ImageGuided, LateralPriorContinuesAWallTowardsTheImageCentre) {
  const cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(128));
  const double wall_depth = 4.0 / 0.6;  // column 20: x = (20 - 80) / 100 = -0.6
  const std::vector<Eigen::Vector3d> wall = {pointOnPixelRay(smallCamera(), 20, 30, wall_depth)};
  mm::DepthCompletionParams p = guidedParams(true);
  p.guided.sky = false;
  p.guided.lambda = 1e-6;
  mm::DepthCompleter completer(2);
  const auto lateral = completer.complete(wall, smallCamera(), {smallImage(), 1}, p, image);
  EXPECT_NEAR(at(lateral, 30, 60), 20.0f, 0.1f);
  EXPECT_NEAR(at(lateral, 30, 70), 40.0f, 0.2f);
  EXPECT_NEAR(at(lateral, 30, 10), wall_depth, 0.05f);
  EXPECT_NEAR(at(lateral, 30, 140), wall_depth, 0.05f);
  // Below the horizon the ground still caps it: row 100 meets the ground 3.25 m away.
  EXPECT_NEAR(at(lateral, 100, 60), 1.3f / 0.4f, 0.05f);
  p.guided.lateral_prior = false;
  const auto own_depth = completer.complete(wall, smallCamera(), {smallImage(), 1}, p, image);
  EXPECT_NEAR(at(own_depth, 30, 60), wall_depth, 0.05f);
  EXPECT_NEAR(at(own_depth, 30, 140), wall_depth, 0.05f);
}

namespace {
/// Three returns at different depths, for the tests of ground_gp's prior.
std::vector<Eigen::Vector3d> threeReturns() {
  return {pointOnPixelRay(smallCamera(), 30, 70, 8.0),
          pointOnPixelRay(smallCamera(), 120, 40, 15.0),
          pointOnPixelRay(smallCamera(), 70, 90, 6.0)};
}

/// Sixteen returns on the camera's horizontal plane (y = 0), one scan plane through the sensor as
/// a 2D radar's, 6-28.5 m away, scattered in azimuth (not on one line, so that the same returns
/// lifted off the plane fit no other plane).
std::vector<Eigen::Vector3d> scanPlaneReturns() {
  std::vector<Eigen::Vector3d> returns;
  for (int i = 0; i < 16; ++i) {
    const double z = 6.0 + 1.5 * i;
    returns.emplace_back(0.5 * z * std::sin(0.9 * i), 0.0, z);
  }
  return returns;
}

cv::Mat uniformGray() {
  return cv::Mat(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(128));
}

/// ground_gp as image_guided runs it for its prior: with the prior's use of the image's colours.
mm::DepthCompletionParams groundGp() {
  mm::DepthCompletionParams gp = guidedParams();
  gp.model = mm::DepthModel::kGroundGp;
  gp.ground.surface_colour_sigma = gp.guided.prior_colour_sigma;
  gp.ground.surface_colour_walls = gp.guided.prior_colour_walls;
  return gp;
}

/// image_guided on ground_gp's prior with a smoother too weak to move evidence and no sky: the
/// prior shows through.
mm::DepthCompletionParams priorShowsThrough() {
  mm::DepthCompletionParams p = guidedParams();
  p.guided.sky = false;
  p.guided.lambda = 1e-9;
  p.guided.ground_gp_prior = true;
  return p;
}

/// ground_gp's depth at every pixel (its prior grid at step 1), the prior of the model below.
mm::DepthMap groundGpAtEveryPixel(mm::DepthCompleter& completer,
                                  const std::vector<Eigen::Vector3d>& returns,
                                  const cv::Mat& image) {
  mm::DepthCompletionParams gp = groundGp();
  gp.guided.prior_step_px = 1;
  return completer.complete(returns, smallCamera(), {smallImage(), 1}, gp, image);
}

/// priorShowsThrough() with the prior at every pixel and a large fixed weight, so that at a
/// return's pixel the prior's share of the mean shows.
constexpr double kLargePriorWeight = 0.5;
mm::DepthCompletionParams priorMixesWithReturns(double weight_above_returns) {
  mm::DepthCompletionParams p = priorShowsThrough();
  p.guided.prior_step_px = 1;
  p.guided.prior_weight = kLargePriorWeight;
  p.guided.prior_reference_density = 0.0;  // the weight as given
  p.guided.prior_weight_above_returns = weight_above_returns;
  return p;
}

/// The depth of the inverse-depth mean of a return (weight `return_weight`) and the prior
/// (`prior_depth`, weight `prior_weight`).
float mixedDepth(double prior_depth, double prior_weight, double depth, double return_weight) {
  return float((prior_weight + return_weight) /
               (prior_weight / prior_depth + return_weight / depth));
}
}  // namespace

// With ground_gp's prediction as the prior and a smoother too weak to move evidence, every pixel
// without a return shows ground_gp's depth (capped at the far clamp) and variance; with the
// model's own prior the same pixels differ.
TEST(ImageGuided, GroundGpPriorIsGroundGpsPrediction) {
  const cv::Mat image = uniformGray();
  const std::vector<Eigen::Vector3d> returns = threeReturns();
  mm::DepthCompleter completer(2);
  const auto ground_gp =
      completer.complete(returns, smallCamera(), {smallImage(), 1}, groundGp(), image);
  mm::DepthCompletionParams p = priorShowsThrough();
  p.guided.prior_step_px = 1;  // at every pixel (the coarser prior grid has its own test below)
  const auto hybrid = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  p.guided.ground_gp_prior = false;
  const auto own = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  int compared = 0, differ = 0;
  for (int r = 0; r < smallImage().height; r += 7) {
    for (int c = 0; c < kCols; c += 7) {
      const float want = std::min(at(ground_gp, r, c), 100.0f);
      ASSERT_NEAR(at(hybrid, r, c), want, 1e-4f * want) << r << " " << c;
      // Where only the prior speaks, its variance is ground_gp's (calibrated) variance.
      const std::size_t i = std::size_t(r) * kCols + c;
      ASSERT_NEAR(hybrid.variance[i], ground_gp.variance[i], 1e-3f * ground_gp.variance[i])
          << r << " " << c;
      differ += std::abs(at(own, r, c) - want) > 0.01f * want;
      ++compared;
    }
  }
  EXPECT_GT(differ, compared / 4);
}

// A 2D scanner's returns (all on one plane through the sensor: nuScenes' front radar) project to
// the rows of that plane, not of the surfaces that returned them: the smoother then ignores the
// image's edges between rows (an image that changes only from row to row acts as a uniform guide)
// and still follows those between columns. Returns off that plane keep every edge.
TEST(ImageGuided, ReturnsOnOneScanPlaneIgnoreTheEdgesBetweenRows) {
  cv::Mat rows_only(smallImage().height, kCols, CV_8UC3, cv::Scalar::all(40));
  rows_only.rowRange(0, 75).setTo(cv::Scalar::all(200));  // an edge between rows 74 and 75
  const std::vector<Eigen::Vector3d> scan_plane = scanPlaneReturns();
  std::vector<Eigen::Vector3d> three_d = scan_plane;
  for (std::size_t i = 0; i < three_d.size(); ++i)
    three_d[i].y() = (i % 2 == 0 ? 0.4 : -0.4);  // 0.4 m above and below: no longer one plane
  mm::DepthCompleter completer(2);
  mm::DepthCompletionParams p = edgeParams();
  const auto on_plane =
      completer.complete(scan_plane, smallCamera(), {smallImage(), 1}, p, rows_only);
  const auto off_plane =
      completer.complete(three_d, smallCamera(), {smallImage(), 1}, p, rows_only);
  p.guided.edges = false;
  const auto on_plane_uniform =
      completer.complete(scan_plane, smallCamera(), {smallImage(), 1}, p, rows_only);
  const auto off_plane_uniform =
      completer.complete(three_d, smallCamera(), {smallImage(), 1}, p, rows_only);
  EXPECT_TRUE(on_plane.stats.ground_single_scan_plane);
  EXPECT_FALSE(off_plane.stats.ground_single_scan_plane);
  EXPECT_EQ(on_plane.depth, on_plane_uniform.depth);
  EXPECT_EQ(on_plane.variance, on_plane_uniform.variance);
  int differ = 0;
  for (std::size_t i = 0; i < off_plane.depth.size(); ++i)
    differ +=
        std::abs(off_plane.depth[i] - off_plane_uniform.depth[i]) > 1e-3f * off_plane.depth[i];
  EXPECT_GT(differ, 100);  // 3D returns: the edge between rows holds
}

// Above the band of the returns' elevations (all but the highest 2 % of them) ground_gp's prior
// weighs prior_weight_above_returns times more. With a smoother too weak to move evidence, a
// return's pixel holds the mean of its return and the prior weighed 1 : w in inverse depth: w
// the prior's weight within the band, ten times it above. A 2D scanner's returns (one scan plane,
// no measured elevation) have no band: the factor changes nothing.
TEST(ImageGuided, GroundGpPriorWeighsMoreAboveTheReturnsBand) {
  const cv::Mat image = uniformGray();
  // 98 returns on rows 60-100 of 120 and two high above them (rows 10 and 20): the top 2 %.
  std::vector<Eigen::Vector3d> returns;
  for (int i = 0; i < 98; ++i)
    returns.push_back(
        pointOnPixelRay(smallCamera(), (i * 13) % 150 + 5, 60 + (i * 7) % 41, 6.0 + 0.2 * i));
  returns.push_back(pointOnPixelRay(smallCamera(), 40, 10, 30.0));
  returns.push_back(pointOnPixelRay(smallCamera(), 120, 20, 4.0));
  mm::DepthCompleter completer(2);
  const auto prior = groundGpAtEveryPixel(completer, returns, image);
  mm::DepthCompletionParams p = priorMixesWithReturns(10.0);
  const auto above = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  const auto mean_of = [&](int u, int v, double depth, double w) {
    // A return far in front of the prior weighs a tenth (the test below): the one at 4 m is.
    const double prior_depth = at(prior, v, u);
    return mixedDepth(prior_depth, w, depth, depth * 1.6 < prior_depth ? 0.1 : 1.0);
  };
  for (const auto& [u, v, depth] : {std::make_tuple(40, 10, 30.0), std::make_tuple(120, 20, 4.0)})
    EXPECT_NEAR(at(above, v, u), mean_of(u, v, depth, 10.0 * kLargePriorWeight), 1e-3f * depth)
        << u << " " << v;
  // A return within the band: the prior's own weight.
  const Eigen::Vector3d& inside = returns[10];
  const int u = (10 * 13) % 150 + 5, v = 60 + (10 * 7) % 41;
  EXPECT_NEAR(at(above, v, u), mean_of(u, v, inside.z(), kLargePriorWeight), 1e-3f * inside.z());
  p.guided.prior_weight_above_returns = 1.0;
  const auto even = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  EXPECT_NEAR(at(even, 10, 40), mean_of(40, 10, 30.0, kLargePriorWeight), 1e-3f * 30.0f);
  EXPECT_GT(std::abs(at(even, 10, 40) - at(above, 10, 40)), 0.1f);
  // The stats say where the band ended: the third highest return, on row 60 (the principal
  // point's, elevation 0); no band with the factor 1.
  EXPECT_NEAR(above.stats.guided_band_top_deg, 0.0, 1e-6);
  EXPECT_TRUE(std::isnan(even.stats.guided_band_top_deg));

  // Returns on one scan plane through the camera (a 2D radar's).
  const std::vector<Eigen::Vector3d> scan_plane = scanPlaneReturns();
  p.guided.prior_weight_above_returns = 1.0;
  const auto plane_even =
      completer.complete(scan_plane, smallCamera(), {smallImage(), 1}, p, image);
  p.guided.prior_weight_above_returns = 10.0;
  const auto plane_above =
      completer.complete(scan_plane, smallCamera(), {smallImage(), 1}, p, image);
  EXPECT_TRUE(plane_above.stats.ground_single_scan_plane);
  EXPECT_TRUE(std::isnan(plane_above.stats.guided_band_top_deg));
  EXPECT_EQ(plane_above.depth, plane_even.depth);
  EXPECT_EQ(plane_above.variance, plane_even.variance);
}

// With ground_gp's prior, a return far nearer than the prior at its pixel (no neighbouring return
// agrees with it: clutter) weighs a tenth of a return; one nearer by less keeps its full weight.
TEST(ImageGuided, GroundGpPriorOutweighsAReturnFarInFrontOfIt) {
  const cv::Mat image = uniformGray();
  // A wall of returns at 18-22 m over rows 50-100, and two returns in front of it near the
  // middle: one at 5 m (far in front), one at 15 m (in front by less than the rule's factor).
  std::vector<Eigen::Vector3d> returns;
  for (int i = 0; i < 60; ++i)
    returns.push_back(
        pointOnPixelRay(smallCamera(), (i * 17) % 140 + 10, 50 + (i * 11) % 51, 18.0 + 0.07 * i));
  returns.push_back(pointOnPixelRay(smallCamera(), 75, 72, 5.0));
  returns.push_back(pointOnPixelRay(smallCamera(), 110, 64, 15.0));
  mm::DepthCompleter completer(2);
  const auto prior = groundGpAtEveryPixel(completer, returns, image);
  const auto out = completer.complete(returns, smallCamera(), {smallImage(), 1},
                                      priorMixesWithReturns(1.0), image);
  const auto mean_of = [&](int u, int v, double depth, double return_weight) {
    return mixedDepth(at(prior, v, u), kLargePriorWeight, depth, return_weight);
  };
  // The precondition: the prior at the 5 m return lies beyond 1.6 x 5 m, at the 15 m one within.
  ASSERT_GT(at(prior, 72, 75), 1.6f * 5.0f);
  ASSERT_LT(at(prior, 64, 110), 1.6f * 15.0f);
  EXPECT_NEAR(at(out, 72, 75), mean_of(75, 72, 5.0, 0.1), 1e-3f * 5.0f);
  EXPECT_GT(std::abs(at(out, 72, 75) - mean_of(75, 72, 5.0, 1.0)), 0.1f);
  EXPECT_NEAR(at(out, 64, 110), mean_of(110, 64, 15.0, 1.0), 1e-3f * 15.0f);
}

// With ground_gp's prior the prior's weight follows the returns' density: a reference density a
// third of the frame's is the same as three times the weight with no reference. The own prior
// (dense input) keeps its weight whatever the reference.
TEST(ImageGuided, GroundGpPriorWeighsWithTheReturnsDensity) {
  const cv::Mat image = twoHalves();
  const std::vector<Eigen::Vector3d> returns = threeReturns();
  const double density = mm::returnDensity(returns.size(), smallCamera(), smallImage());
  mm::DepthCompleter completer(2);
  mm::DepthCompletionParams p = guidedParams();
  p.guided.ground_gp_prior = true;
  p.guided.prior_reference_density = density / 3.0;
  const auto scaled = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  p.guided.prior_reference_density = 0.0;
  const auto fixed = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  p.guided.prior_weight *= 3.0;
  const auto tripled = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  ASSERT_EQ(scaled.depth.size(), tripled.depth.size());
  int differ = 0;
  for (std::size_t i = 0; i < scaled.depth.size(); ++i) {
    ASSERT_NEAR(scaled.depth[i], tripled.depth[i], 1e-5f * tripled.depth[i]) << i;
    ASSERT_NEAR(scaled.variance[i], tripled.variance[i], 1e-4f * tripled.variance[i]) << i;
    differ += std::abs(scaled.depth[i] - fixed.depth[i]) > 1e-3f * fixed.depth[i];
  }
  EXPECT_GT(differ, 100);  // the weight moved the depth
  // The stats say which density the frame had and which weight followed.
  EXPECT_NEAR(scaled.stats.guided_return_density, density, 1e-12);
  EXPECT_NEAR(scaled.stats.guided_prior_weight, 3.0 * guidedParams().guided.prior_weight, 1e-12);
  EXPECT_NEAR(fixed.stats.guided_prior_weight, guidedParams().guided.prior_weight, 1e-12);
  EXPECT_NEAR(tripled.stats.guided_prior_weight, 3.0 * guidedParams().guided.prior_weight, 1e-12);
  const auto ground_gp = completer.complete(returns, smallCamera(), {smallImage(), 1}, groundGp());
  EXPECT_EQ(ground_gp.stats.guided_return_density, -1.0);  // not image_guided
  EXPECT_EQ(ground_gp.stats.guided_prior_weight, -1.0);

  // Dense input: the own prior, whatever the reference density.
  std::vector<Eigen::Vector3d> dense;
  for (int v = 40; v < smallImage().height; v += 2) {
    for (int u = 0; u < kCols; u += 2)
      dense.push_back(pointOnPixelRay(smallCamera(), u, v, u < 80 ? 6.0 : 18.0));
  }
  p = guidedParams();
  p.guided.ground_gp_prior = true;
  p.ground.input = mm::GroundPriorParams::Input::kDense;
  const auto dense_default = completer.complete(dense, smallCamera(), {smallImage(), 1}, p, image);
  p.guided.prior_reference_density = 0.0;
  const auto dense_fixed = completer.complete(dense, smallCamera(), {smallImage(), 1}, p, image);
  EXPECT_EQ(dense_default.depth, dense_fixed.depth);
  EXPECT_EQ(dense_default.variance, dense_fixed.variance);
  EXPECT_EQ(dense_default.stats.guided_prior_weight, guidedParams().guided.prior_weight);
  EXPECT_GT(dense_default.stats.guided_return_density, density);
}

// On a prior grid four image pixels apart, the prior is ground_gp's prediction on that grid (at
// every 4th pixel of every 4th row it is ground_gp's output at stride 4) interpolated between,
// close to ground_gp's prediction at every pixel. At output stride 4 the prior grid is the output
// grid: the same depth as with a step of one pixel.
TEST(ImageGuided, CoarserPriorGridIsGroundGpOnThatGridInterpolated) {
  const cv::Mat image = uniformGray();
  const std::vector<Eigen::Vector3d> returns = threeReturns();
  mm::DepthCompleter completer(2);
  const auto ground_gp =
      completer.complete(returns, smallCamera(), {smallImage(), 1}, groundGp(), image);
  const auto ground_gp_coarse =
      completer.complete(returns, smallCamera(), {smallImage(), 4}, groundGp(), image);
  mm::DepthCompletionParams p = priorShowsThrough();
  p.guided.prior_step_px = 4;
  const auto coarse = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  const int coarse_cols = ground_gp_coarse.grid.cols();
  int on_lattice = 0;
  double relative_error = 0.0;
  for (int r = 0; r < smallImage().height; ++r) {
    for (int c = 0; c < kCols; ++c) {
      // A return's own pixel shows the return (weight 1), not the prior (the wall of a return
      // between it and the image centre makes them differ there).
      const bool at_return = (r == 70 && c == 30) || (r == 40 && c == 120) || (r == 90 && c == 70);
      if (r % 4 == 0 && c % 4 == 0 && !at_return) {
        const float sample =
            std::min(ground_gp_coarse.depth[std::size_t(r / 4) * coarse_cols + c / 4], 100.0f);
        ASSERT_NEAR(at(coarse, r, c), sample, 1e-4f * sample) << r << " " << c;
        ++on_lattice;
      }
      const float full = std::min(at(ground_gp, r, c), 100.0f);
      relative_error += std::abs(at(coarse, r, c) - full) / full;
    }
  }
  EXPECT_EQ(on_lattice, 30 * 40 - 1);  // (40, 120) is a return's pixel
  const double mean_relative_error = relative_error / (double(smallImage().height) * kCols);
  EXPECT_LT(mean_relative_error, 0.01);
  EXPECT_GT(mean_relative_error, 0.0);  // an approximation, not ground_gp at every pixel
  // Stride 4: the prior grid is the output grid.
  const auto step4_stride4 =
      completer.complete(returns, smallCamera(), {smallImage(), 4}, p, image);
  p.guided.prior_step_px = 1;
  const auto step1_stride4 =
      completer.complete(returns, smallCamera(), {smallImage(), 4}, p, image);
  EXPECT_EQ(step4_stride4.depth, step1_stride4.depth);
  p.guided.prior_step_px = 0;
  EXPECT_THROW(completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image),
               mm::InputError);
}

// ground_gp's prediction is the prior on sparse input only: on input handled as dense (LiDAR;
// the auto choice between the modes has its own tests with ground_gp) switching it on changes
// nothing, while on the same scan thinned to radar density and handled as sparse it does.
TEST(ImageGuided, GroundGpPriorOnlyOnSparseInput) {
  std::vector<Eigen::Vector3d> dense;
  for (int v = 40; v < smallImage().height; ++v) {
    for (int u = 0; u < kCols; ++u) {
      dense.push_back(pointOnPixelRay(smallCamera(), u, v, u < 80 ? 6.0 + 0.02 * v : 18.0));
    }
  }
  std::vector<Eigen::Vector3d> sparse;
  for (std::size_t i = 0; i < dense.size(); i += 97)
    sparse.push_back(dense[i]);
  mm::DepthCompleter completer(2);
  mm::DepthCompletionParams p = guidedParams(true);
  const cv::Mat image = twoHalves();
  using Input = mm::GroundPriorParams::Input;
  const auto complete = [&](const std::vector<Eigen::Vector3d>& points, bool ground_gp_prior) {
    p.guided.ground_gp_prior = ground_gp_prior;
    p.ground.input = points.size() == dense.size() ? Input::kDense : Input::kSparse;
    return completer.complete(points, smallCamera(), {smallImage(), 1}, p, image);
  };
  const auto dense_own = complete(dense, false);
  const auto dense_gp = complete(dense, true);
  EXPECT_EQ(dense_gp.stats.ground_mode, "dense");
  EXPECT_EQ(dense_own.depth, dense_gp.depth);
  EXPECT_EQ(dense_own.variance, dense_gp.variance);
  const auto sparse_own = complete(sparse, false);
  const auto sparse_gp = complete(sparse, true);
  EXPECT_NE(sparse_gp.stats.ground_mode, "dense");
  EXPECT_NE(sparse_own.depth, sparse_gp.depth);
}

// lambda and prior_weight are per image pixel: at output stride 2 the depth matches the full-
// resolution depth at the same image pixels, and the parameters taken per grid pixel (lambda 4x
// the reach, a quarter of the prior's weight: what the model did before) match it worse.
TEST(ImageGuided, StrideKeepsTheSmoothersReachOnTheImage) {
  const std::vector<Eigen::Vector3d> returns = {pointOnPixelRay(smallCamera(), 30, 20, 7.0),
                                                pointOnPixelRay(smallCamera(), 60, 100, 12.0),
                                                pointOnPixelRay(smallCamera(), 100, 60, 4.0)};
  const cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(100));
  mm::DepthCompleter completer(2);
  mm::DepthCompletionParams p = guidedParams();
  p.guided.sky = false;
  const auto full = completer.complete(returns, smallCamera(), {smallImage(), 1}, p, image);
  const auto strided = completer.complete(returns, smallCamera(), {smallImage(), 2}, p, image);
  p.guided.lambda *= 4.0;
  p.guided.prior_weight /= 4.0;
  const auto per_grid_pixel =
      completer.complete(returns, smallCamera(), {smallImage(), 2}, p, image);
  const int half_cols = kCols / 2;
  double error = 0.0, error_per_grid_pixel = 0.0;
  for (int r = 0; r < smallImage().height; r += 2) {
    for (int c = 0; c < kCols; c += 2) {
      const float want = at(full, r, c);
      const std::size_t i = std::size_t(r / 2) * half_cols + c / 2;
      error += std::abs(strided.depth[i] - want) / want;
      error_per_grid_pixel += std::abs(per_grid_pixel.depth[i] - want) / want;
    }
  }
  const double pixels = double(smallImage().height / 2) * half_cols;
  EXPECT_LT(error / pixels, 0.01);
  EXPECT_GT(error_per_grid_pixel, 5.0 * error);
}

// On a grid twice as coarse the smoother reaches as far (lambda / 4) and still stops at the edge:
// each half keeps its return's depth up to a pixel or two from the edge.
TEST(ImageGuided, CoarserSmoothingGridKeepsTheEdgeAndTheDepths) {
  mm::DepthCompletionParams p = edgeParams();
  mm::DepthCompleter completer(2);
  const auto fine = twoHalvesDepth(completer, p);
  p.guided.smooth_scale = 2;
  const auto coarse = twoHalvesDepth(completer, p);
  for (int c : {10, 40, 76, 84, 120, 150}) {
    EXPECT_NEAR(at(coarse, 60, c), at(fine, 60, c), 0.05f * at(fine, 60, c)) << c;
  }
  EXPECT_GT(at(coarse, 80, 84) - at(coarse, 80, 76), 0.5f * (at(fine, 80, 84) - at(fine, 80, 76)));
  p.guided.smooth_scale = 0;
  EXPECT_THROW(twoHalvesDepth(completer, p), mm::InputError);
}

TEST(ImageGuided, BrightUniformTopIsSkyAtTheFarClampWithItsVariance) {
  cv::Mat image = twoHalves();
  image.rowRange(0, 30).setTo(cv::Scalar(230, 210, 190));  // sky above row 30
  mm::DepthCompletionParams p = guidedParams();
  mm::DepthCompleter completer(2);
  const auto map = completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, p, image);
  EXPECT_FLOAT_EQ(at(map, 5, 20), 100.0f);
  EXPECT_FLOAT_EQ(map.variance[std::size_t(5) * kCols + 20], 1.0f);
  // The dark facade below the sky line is not sky (darker than sky_brightness).
  EXPECT_LT(at(map, 40, 20), 100.0f);
  p.guided.sky = false;
  const auto no_sky = completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, p, image);
  EXPECT_NE(no_sky.variance[std::size_t(5) * kCols + 20], 1.0f);
}

// ground_gp takes the same sky when asked (ground.image_sky, config/lidar.yaml): the bright blue
// rows above the returns go to the far clamp with the sky's variance; without the switch, or
// without an image, ground_gp's own prediction stays.
TEST(ImageGuided, GroundGpTakesTheImagesSkyWhenAsked) {
  cv::Mat image = twoHalves();
  image.rowRange(0, 30).setTo(cv::Scalar(230, 210, 190));  // sky above row 30
  mm::DepthCompletionParams p;
  p.model = mm::DepthModel::kGroundGp;
  p.threads = 2;
  ASSERT_FALSE(p.ground.image_sky);
  EXPECT_TRUE(p.readsImage());   // the dense mode's vote may use the colours
  EXPECT_FALSE(p.needsImage());  // ... but goes without it
  p.ground.dense_vote_colour_sigma = 0.0;
  EXPECT_FALSE(p.readsImage());
  p.ground.surface_colour_sigma = 20.0;
  EXPECT_TRUE(p.readsImage());
  EXPECT_FALSE(p.needsImage());
  p.ground.surface_colour_sigma = 0.0;
  mm::DepthCompleter completer(2);
  const auto plain = completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, p, image);
  p.ground.image_sky = true;
  EXPECT_TRUE(p.readsImage());
  EXPECT_TRUE(p.needsImage());
  const auto sky = completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, p, image);
  const auto no_image =
      completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, p, cv::Mat());
  const std::size_t top = std::size_t(5) * kCols + 20, below = std::size_t(60) * kCols + 20;
  EXPECT_FLOAT_EQ(sky.depth[top], 100.0f);
  EXPECT_FLOAT_EQ(sky.variance[top], 1.0f);
  EXPECT_NE(plain.depth[top], 100.0f);
  EXPECT_EQ(no_image.depth[top], plain.depth[top]);
  // Below the sky line ground_gp's prediction is untouched.
  EXPECT_EQ(sky.depth[below], plain.depth[below]);
  EXPECT_EQ(sky.variance[below], plain.variance[below]);
}

// The sky is found before the prediction exists (ground_gp computes it while its triangulation
// runs) and applied afterwards: exactly the mask's pixels change, and a mask of another grid is
// refused rather than written past the prediction.
TEST(ImageGuided, SkyMaskSetsExactlyItsPixelsAndRefusesAnotherSize) {
  mm::ImageGuidedParams g;
  g.far_depth = 80.0;
  g.sky_sigma = 3.0;
  mm::PixelPredictions out;
  out.mean.assign(6, 5.0f);
  out.variance.assign(6, 0.5f);
  const std::vector<std::uint8_t> sky = {0, 1, 0, 0, 1, 1};
  mm::applySkyMask(sky, g, out);
  for (std::size_t i = 0; i < sky.size(); ++i) {
    EXPECT_FLOAT_EQ(out.mean[i], sky[i] ? 80.0f : 5.0f) << i;
    EXPECT_FLOAT_EQ(out.variance[i], sky[i] ? 9.0f : 0.5f) << i;
  }
  EXPECT_THROW(mm::applySkyMask(std::vector<std::uint8_t>(7, 1), g, out), mm::InputError);
  EXPECT_FLOAT_EQ(out.mean[0], 5.0f);
}

TEST(ImageGuided, SkyStopsAtTheFirstReturnOfAColumn) {
  const cv::Mat bright(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(220));
  std::vector<float> far(std::size_t(smallImage().height) * kCols, 100.0f);
  std::vector<int> top_return(kCols, smallImage().height);
  top_return[10] = 12;
  const auto sky = mm::skyMask(bright, far, 100.0f, top_return, 12.0, 120.0, 10.0);
  EXPECT_EQ(sky[std::size_t(11) * kCols + 10], 1);
  EXPECT_EQ(sky[std::size_t(12) * kCols + 10], 0);
  EXPECT_EQ(sky[std::size_t(100) * kCols + 11], 1);
}

// A bright plain facade reaching the top of the image (beige, brick, a sign) is flat and bright
// like the sky; its colour tells it apart: skies are blue or gray, at most sky_max_warmth redder
// than blue.
TEST(ImageGuided, WarmBrightPlainSurfaceAtTheTopIsNotSky) {
  const cv::Size size(smallImage().width, smallImage().height);
  const std::vector<float> far(std::size_t(size.height) * kCols, 100.0f);
  const std::vector<int> no_return(kCols, size.height);
  const auto skyAt = [&](const cv::Scalar& bgr, double max_warmth) {
    const cv::Mat image(size, CV_8UC3, bgr);
    return mm::skyMask(image, far, 100.0f, no_return, 12.0, 120.0, max_warmth)[5 * kCols + 20];
  };
  EXPECT_EQ(skyAt(cv::Scalar(235, 200, 170), 10.0), 1);   // blue sky
  EXPECT_EQ(skyAt(cv::Scalar(214, 214, 216), 10.0), 1);   // overcast, a trace warmer than blue
  EXPECT_EQ(skyAt(cv::Scalar(150, 205, 230), 10.0), 0);   // beige facade
  EXPECT_EQ(skyAt(cv::Scalar(150, 205, 230), 255.0), 1);  // without the colour test
  // Above a warm band the column's sky ends at the band.
  cv::Mat image(size, CV_8UC3, cv::Scalar(235, 200, 170));
  image.rowRange(20, 30).setTo(cv::Scalar(150, 205, 230));
  const auto sky = mm::skyMask(image, far, 100.0f, no_return, 255.0, 120.0, 10.0);
  EXPECT_EQ(sky[std::size_t(10) * kCols + 20], 1);
  EXPECT_EQ(sky[std::size_t(25) * kCols + 20], 0);
  EXPECT_EQ(sky[std::size_t(40) * kCols + 20], 0);
}

TEST(ImageGuided, VarianceGrowsAwayFromTheReturnsAndIsFiniteEverywhere) {
  mm::DepthCompletionParams p = guidedParams();
  p.guided.sky = false;
  mm::DepthCompleter completer(2);
  const auto map =
      completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, p, twoHalves());
  for (std::size_t i = 0; i < map.variance.size(); ++i) {
    ASSERT_TRUE(std::isfinite(map.variance[i]) && map.variance[i] > 0.0f) << i;
    ASSERT_TRUE(map.depth[i] > 0.0f && map.depth[i] <= 100.0f) << i;
  }
  // Relative to depth: tight at a return, wider where only the prior speaks.
  const auto relative = [&](int row, int col) {
    return map.variance[std::size_t(row) * kCols + col] / (at(map, row, col) * at(map, row, col));
  };
  EXPECT_LT(relative(80, 60), relative(115, 5));
}

TEST(ImageGuided, StrideGridSamplesTheImageAtItsNodes) {
  cv::Mat image(5, 7, CV_8UC1);
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 7; ++c)
      image.at<std::uint8_t>(r, c) = std::uint8_t(10 * r + c);
  const cv::Mat guide = mm::guideOnGrid(image, {{5, 7}, 2});
  ASSERT_EQ(guide.rows, 3);
  ASSERT_EQ(guide.cols, 4);
  EXPECT_EQ(guide.at<cv::Vec3b>(2, 3)[0], 10 * 4 + 6);
}

TEST(ImageGuided, MissingOrMismatchedImageIsAnInputError) {
  mm::DepthCompleter completer(2);
  EXPECT_THROW(completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, guidedParams()),
               mm::InputError);
  const cv::Mat small(10, 10, CV_8UC3, cv::Scalar::all(0));
  EXPECT_THROW(
      completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, guidedParams(), small),
      mm::InputError);
  const cv::Mat floats(smallImage().height, smallImage().width, CV_32FC3);
  EXPECT_THROW(
      completer.complete(twoReturns(), smallCamera(), {smallImage(), 1}, guidedParams(), floats),
      mm::InputError);
}

TEST(ImageGuided, NoReturnsGiveTheSmoothedGroundPrior) {
  mm::DepthCompletionParams p = guidedParams();
  p.guided.sky = false;
  mm::DepthCompleter completer(2);
  const auto map = completer.complete({}, smallCamera(), {smallImage(), 1}, p, twoHalves());
  // The smoothed ground prior: nearer towards the bottom of the image, within (0, far].
  EXPECT_LT(at(map, 115, 40), at(map, 90, 40));
  for (float d : map.depth)
    ASSERT_TRUE(d > 0.0f && d <= 100.0f);
}

// The radar default (ground_gp's prediction as the prior) on degenerate scans: none, one return,
// returns behind the camera or not finite, many returns on one pixel, a return at 0.01 m and one
// at 10 km. Each gives finite, positive depth and variance on every pixel, or an InputError.
TEST(ImageGuided, GroundGpPriorSurvivesDegenerateScans) {
  mm::DepthCompletionParams p;
  p.model = mm::DepthModel::kImageGuided;
  p.threads = 2;
  ASSERT_TRUE(p.guided.ground_gp_prior);
  const double nan = std::nan("");
  const std::vector<std::vector<Eigen::Vector3d>> scans = {
      {},
      {pointOnPixelRay(smallCamera(), 60, 80, 9.0)},
      {{0.0, 0.0, -5.0}, {1.0, 2.0, -0.5}},
      {{nan, 0.0, 5.0}, {0.0, std::numeric_limits<double>::infinity(), 5.0}},
      std::vector<Eigen::Vector3d>(50, pointOnPixelRay(smallCamera(), 100, 40, 6.0)),
      {pointOnPixelRay(smallCamera(), 70, 70, 0.01), pointOnPixelRay(smallCamera(), 20, 20, 1e4)},
  };
  mm::DepthCompleter completer(2);
  int completed = 0;
  for (std::size_t k = 0; k < scans.size(); ++k) {
    try {
      const auto map =
          completer.complete(scans[k], smallCamera(), {smallImage(), 1}, p, twoHalves());
      for (std::size_t i = 0; i < map.depth.size(); ++i) {
        ASSERT_TRUE(std::isfinite(map.depth[i]) && map.depth[i] > 0.0f) << k << " " << i;
        ASSERT_TRUE(std::isfinite(map.variance[i]) && map.variance[i] > 0.0f) << k << " " << i;
      }
      ++completed;
    } catch (const mm::InputError& e) {
      SUCCEED() << "scan " << k << ": " << e.what();
    }
  }
  EXPECT_GE(completed, 4);  // at least the empty, single, repeated and extreme scans complete
}

namespace {
// A far wall (a facade, beige) on the left half of the image and a near object (a car, reddish) on
// the right half, a return every 20th pixel; and the same returns flattened onto one scan plane
// (a 2D radar: elevation not measured), which keeps each on its side of the image.
struct ColourScans {
  cv::Mat image;
  std::vector<Eigen::Vector3d> spread, flat;
};
ColourScans colourScans() {
  ColourScans s;
  s.image = cv::Mat(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar(40, 60, 180));
  s.image.colRange(0, 80).setTo(cv::Scalar(150, 190, 200));
  for (int u = 5; u < kCols; u += 20) {
    for (int v = 5; v < smallImage().height; v += 20) {
      const Eigen::Vector3d p = pointOnPixelRay(smallCamera(), u, v, u < 80 ? 30.0 : 6.0);
      s.spread.push_back(p);
      s.flat.push_back({p.x(), 0.4, p.z()});
    }
  }
  return s;
}
}  // namespace

// The prior's colour weighing changes the radar default's depth where returns of two colours meet,
// and is left out for returns on one scan plane, whose pixel is not where they were seen (there
// the colours alone would have changed the prior: checked on the prior itself).
TEST(ImageGuided, PriorColoursApplyOnlyToReturnsWithMeasuredElevation) {
  const ColourScans scans = colourScans();
  mm::DepthCompletionParams with;
  with.model = mm::DepthModel::kImageGuided;
  with.threads = 2;
  ASSERT_GT(with.guided.prior_colour_sigma, 0.0);  // on by default
  with.guided.sky = false;                         // the facade is bright and plain
  // A regular grid of returns on two planes looks like LiDAR rings to the automatic mode.
  with.ground.input = mm::GroundPriorParams::Input::kSparse;
  mm::DepthCompletionParams without = with;
  without.guided.prior_colour_sigma = 0.0;
  mm::DepthCompleter completer(2);
  const auto complete = [&](const std::vector<Eigen::Vector3d>& points,
                            const mm::DepthCompletionParams& p) {
    return completer.complete(points, smallCamera(), {smallImage(), 1}, p, scans.image);
  };
  EXPECT_NE(complete(scans.spread, with).depth, complete(scans.spread, without).depth);
  const mm::DepthMap flat_with = complete(scans.flat, with);
  const mm::DepthMap flat_without = complete(scans.flat, without);
  EXPECT_EQ(flat_with.depth, flat_without.depth);
  EXPECT_EQ(flat_with.variance, flat_without.variance);
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  const mm::SurfaceColours colours(scans.image, smallImage(), with.guided.prior_colour_sigma);
  const auto flat = mm::toAngularSamples(scans.flat);
  EXPECT_NE(
      mm::nearestSurfaceRows(flat, angles, 8, 2, 4, pool, nullptr, mm::SurfacePriorImage{&colours})
          .depth_rows,
      mm::nearestSurfaceRows(flat, angles, 8, 2, 4, pool).depth_rows);
}
