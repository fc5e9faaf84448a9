// Splatting in both modes on analytic scenes (GEN3C's published renderer).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"

namespace mm = multimodal_nvs;

namespace {

constexpr int kH = 48, kW = 64;
const mm::PinholeIntrinsics kK{40.0, 40.0, 31.5, 23.5};

cv::Mat randomImage(int seed) {
  cv::Mat image(kH, kW, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

mm::Trajectory single(const Eigen::Matrix4d& w2c, const mm::PinholeIntrinsics& k = kK) {
  mm::Trajectory t;
  t.size = {kH, kW};
  t.cameras.push_back({w2c, k});
  return t;
}

Eigen::Matrix4d translation(double x, double y, double z) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 3) = x;
  m(1, 3) = y;
  m(2, 3) = z;
  return m;
}

mm::SplatParams mode(mm::SplatMode m) {
  mm::SplatParams p;
  p.mode = m;
  return p;
}

class BothModes : public ::testing::TestWithParam<mm::SplatMode> {};

}  // namespace

TEST_P(BothModes, IdentityReproducesInputColoursExactly) {
  // A slanted, bumpy surface and holes in the kept mask.
  cv::Mat depth(kH, kW, CV_32FC1);
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u)
      depth.at<float>(v, u) = 3.0f + 0.05f * u + 0.3f * ((u * 7 + v * 3) % 5);
  }
  depth(cv::Rect(10, 10, 8, 6)).setTo(-1.0f);
  const cv::Mat image = randomImage(1);
  const mm::ColoredCloud cloud = mm::backproject(depth, image, kK);
  mm::PointSplatter splatter(2);
  const auto frames =
      splatter.render(cloud, single(Eigen::Matrix4d::Identity()), 0, 1, mode(GetParam()));
  const mm::RenderedFrame& f = frames[0];
  int covered = 0;
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      if (depth.at<float>(v, u) <= 0.0f) {
        EXPECT_EQ(f.mask.at<std::uint8_t>(v, u), 0) << u << "," << v;
        continue;
      }
      ASSERT_EQ(f.mask.at<std::uint8_t>(v, u), 255) << u << "," << v;
      ASSERT_EQ(f.bgr.at<cv::Vec3b>(v, u), image.at<cv::Vec3b>(v, u)) << u << "," << v;
      EXPECT_NEAR(f.depth.at<float>(v, u), depth.at<float>(v, u), 1e-4f);
      ++covered;
    }
  }
  EXPECT_EQ(covered, kH * kW - 48);
}

TEST_P(BothModes, FrontoParallelPlaneShiftsByDisparity) {
  // Plane at Z = 8 m; the camera moves 0.4 m to the right (w2c translates points by -0.4 m in x),
  // so the image moves left by fx * 0.4 / 8 = 2 pixels exactly.
  const float z = 8.0f;
  cv::Mat depth(kH, kW, CV_32FC1, cv::Scalar(z));
  const cv::Mat image = randomImage(2);
  const mm::ColoredCloud cloud = mm::backproject(depth, image, kK);
  mm::PointSplatter splatter(1);
  const auto frames =
      splatter.render(cloud, single(translation(-0.4, 0.0, 0.0)), 0, 1, mode(GetParam()));
  const mm::RenderedFrame& f = frames[0];
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      if (u >= kW - 2) {
        EXPECT_EQ(f.mask.at<std::uint8_t>(v, u), 0) << "disoccluded border " << u;
        continue;
      }
      ASSERT_EQ(f.bgr.at<cv::Vec3b>(v, u), image.at<cv::Vec3b>(v, u + 2)) << u << "," << v;
      EXPECT_NEAR(f.depth.at<float>(v, u), z, 1e-4f);
    }
  }
}

TEST_P(BothModes, NearSurfaceOccludesFarSurface) {
  // Left half far (20 m, blue), right half near (4 m, red). Moving the camera 0.5 m to the right
  // shifts the near half left by fx * 0.5 / 4 = 5 px and the far half by 1 px: the near surface
  // must cover the far one where they overlap, never the other way round.
  cv::Mat depth(kH, kW, CV_32FC1, cv::Scalar(20.0f));
  depth.colRange(kW / 2, kW).setTo(4.0f);
  cv::Mat image(kH, kW, CV_8UC3, cv::Scalar(255, 0, 0));
  image.colRange(kW / 2, kW).setTo(cv::Scalar(0, 0, 255));
  const mm::ColoredCloud cloud = mm::backproject(depth, image, kK);
  mm::PointSplatter splatter(1);
  const auto frames =
      splatter.render(cloud, single(translation(-0.5, 0.0, 0.0)), 0, 1, mode(GetParam()));
  const mm::RenderedFrame& f = frames[0];
  for (int v = 0; v < kH; ++v) {
    // Near half now starts at 32 - 5 = 27; the far half ends at 31 - 1 = 30.
    for (int u = 27; u < kW - 5; ++u) {
      const cv::Vec3b c = f.bgr.at<cv::Vec3b>(v, u);
      EXPECT_EQ(c, cv::Vec3b(0, 0, 255)) << u << "," << v;
      EXPECT_NEAR(f.depth.at<float>(v, u), 4.0f, 1e-3f);
    }
    EXPECT_EQ(f.bgr.at<cv::Vec3b>(v, 20), cv::Vec3b(255, 0, 0));
  }
}

INSTANTIATE_TEST_SUITE_P(Splatting, BothModes,
                         ::testing::Values(mm::SplatMode::kGen3c, mm::SplatMode::kZbuffer),
                         [](const auto& info) { return mm::toString(info.param); });

TEST(Splatting, Gen3cHolesAreMinusOneAndMasksBinary) {
  cv::Mat depth(kH, kW, CV_32FC1, cv::Scalar(5.0f));
  depth(cv::Rect(20, 10, 12, 12)).setTo(0.0f);
  const mm::ColoredCloud cloud = mm::backproject(depth, randomImage(3), kK);
  mm::PointSplatter splatter(1);
  const auto frames = splatter.render(cloud, single(translation(0.13, -0.07, 0.2)), 0, 1,
                                      mode(mm::SplatMode::kGen3c));
  const mm::RenderedFrame& f = frames[0];
  int holes = 0;
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const std::uint8_t m = f.mask.at<std::uint8_t>(v, u);
      ASSERT_TRUE(m == 0 || m == 255);
      const cv::Vec3f s = f.signed_bgr.at<cv::Vec3f>(v, u);
      if (m == 0) {
        ++holes;
        EXPECT_EQ(s, cv::Vec3f(-1, -1, -1));
        EXPECT_EQ(f.bgr.at<cv::Vec3b>(v, u), cv::Vec3b(0, 0, 0));
      } else {
        for (int c = 0; c < 3; ++c)
          EXPECT_TRUE(s[c] >= -1.0f && s[c] <= 1.0f);
      }
    }
  }
  EXPECT_GT(holes, 50);
}

TEST(Splatting, ZbufferFootprintKeepsApproachedSurfaceClosed) {
  // Walking 4 m towards a wall 8 m away doubles its size: without a growing footprint every
  // other pixel would be a hole.
  cv::Mat depth(kH, kW, CV_32FC1, cv::Scalar(8.0f));
  const mm::ColoredCloud cloud = mm::backproject(depth, randomImage(4), kK);
  mm::PointSplatter splatter(1);
  const mm::Trajectory t = single(translation(0.0, 0.0, -4.0));
  mm::SplatParams p = mode(mm::SplatMode::kZbuffer);
  const auto closed = splatter.render(cloud, t, 0, 1, p);
  EXPECT_EQ(cv::countNonZero(closed[0].mask), kH * kW);
  p.grow_footprint = false;
  const auto open = splatter.render(cloud, t, 0, 1, p);
  EXPECT_LT(cv::countNonZero(open[0].mask), kH * kW * 0.4);
}

TEST(Splatting, Gen3cBatchSharesNormaliserAndThreadsDoNotMatter) {
  cv::Mat depth(kH, kW, CV_32FC1, cv::Scalar(6.0f));
  depth.colRange(0, 20).setTo(30.0f);
  const mm::ColoredCloud cloud = mm::backproject(depth, randomImage(5), kK);
  mm::Trajectory t;
  t.size = {kH, kW};
  for (int i = 0; i < 5; ++i)
    t.cameras.push_back({translation(0.1 * i, 0.0, -0.3 * i), kK});
  const mm::SplatParams p = mode(mm::SplatMode::kGen3c);
  mm::PointSplatter one(1), two(2);
  const auto all = two.render(cloud, t, 0, 5, p);
  // Frame 3 alone must equal frame 3 of the whole run (its batch mate 2 is still considered).
  const auto alone = one.render(cloud, t, 3, 1, p);
  EXPECT_EQ(cv::norm(all[3].signed_bgr, alone[0].signed_bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(all[3].depth, alone[0].depth, cv::NORM_INF), 0.0);
  EXPECT_THROW(one.render(cloud, t, 4, 2, p), mm::InputError);
  EXPECT_THROW(one.render(mm::ColoredCloud(), t, 0, 1, p), mm::InputError);
  EXPECT_THROW(mm::parseSplatMode("ewa"), mm::InputError);
}
