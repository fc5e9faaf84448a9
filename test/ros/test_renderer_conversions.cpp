// The conditioning renderer's conversions and its Config <-> settings mapping: plain gtest, no
// master.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "renderer_test_sets.hpp"

namespace mm = multimodal_nvs;
namespace rc = multimodal_nvs::ros_conversions;
namespace enc = sensor_msgs::image_encodings;

namespace {

rc::RendererFault faultOf(const Set& set) {
  rc::RendererInput input;
  return rc::rendererInputFromMessages(set.image, set.depth, set.mask, set.info, true, input).fault;
}

}  // namespace

TEST(RendererSettings, DefaultsAreGen3cAndRoundTrip) {
  const auto defaults = mm::ConditioningRendererConfig::__getDefault__();
  const mm::ConditioningRendererSettings s = mm::rendererSettingsFromConfig(defaults);
  EXPECT_EQ(s.source, mm::TrajectorySource::kTf);
  EXPECT_EQ(s.world_frame, "odom");
  EXPECT_EQ(s.splat.mode, mm::SplatMode::kGen3c);
  EXPECT_EQ(s.renderSize(), (mm::ImageSize{704, 1280}));
  EXPECT_EQ(s.num_frames, 121);
  EXPECT_TRUE(s.backprojection.resize_to_render);
  EXPECT_TRUE(s.export_dir.empty());
  mm::ConditioningRendererConfig back;
  mm::writeRendererSettingsToConfig(s, back);
  EXPECT_EQ(back.trajectory_source, defaults.trajectory_source);
  EXPECT_EQ(back.splat, defaults.splat);
  EXPECT_EQ(back.preset, defaults.preset);
  EXPECT_EQ(back.render_height, defaults.render_height);
  EXPECT_EQ(back.render_width, defaults.render_width);
  EXPECT_EQ(back.resize_depth, defaults.resize_depth);
  EXPECT_EQ(back.num_frames, defaults.num_frames);
  EXPECT_FLOAT_EQ(back.edge_threshold, defaults.edge_threshold);
}

TEST(RendererSettings, ResizeAutoResamplesLargeGridsForGen3cOnly) {
  auto config = mm::ConditioningRendererConfig::__getDefault__();  // gen3c, auto, 704x1280
  auto resized = [&](mm::ImageSize grid) {
    return mm::keyframeBackprojection(mm::rendererSettingsFromConfig(config), grid)
        .resize_to_render;
  };
  EXPECT_TRUE(resized({1216, 1936}));  // VoD at full resolution: GEN3C's own case
  EXPECT_TRUE(resized({704, 1280}));
  EXPECT_FALSE(resized({608, 968}));  // the depth nodelet's stride-2 grid
  config.splat = "zbuffer";
  EXPECT_FALSE(resized({1216, 1936}));
  config.resize_depth = "yes";
  EXPECT_TRUE(resized({608, 968}));
  config.splat = "gen3c";
  config.resize_depth = "no";
  EXPECT_FALSE(resized({1216, 1936}));
}

TEST(RendererSettings, BadValuesThrowNamingTheParameter) {
  const auto good = mm::ConditioningRendererConfig::__getDefault__();
  auto expectThrow = [&](const std::function<void(mm::ConditioningRendererConfig&)>& breakIt,
                         const std::string& expected) {
    auto config = good;
    breakIt(config);
    try {
      mm::rendererSettingsFromConfig(config);
      ADD_FAILURE() << "no error for " << expected;
    } catch (const mm::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  expectThrow([](auto& c) { c.trajectory_source = "gps"; }, "trajectory_source");
  expectThrow([](auto& c) { c.splat = "magic"; }, "magic");
  expectThrow([](auto& c) { c.preset = "sideways"; }, "sideways");
  expectThrow([](auto& c) { c.resize_depth = "maybe"; }, "resize_depth");
  expectThrow([](auto& c) { c.render_width = 0; }, "render_width");
  expectThrow([](auto& c) { c.num_frames = 0; }, "num_frames");
  expectThrow([](auto& c) { c.world_frame = ""; }, "world_frame");
}

TEST(RendererConversions, StrideGridOfTheImage) {
  int s = 0;
  EXPECT_TRUE(rc::gridStride({120, 160}, {120, 160}, s).ok());
  EXPECT_EQ(s, 1);
  EXPECT_TRUE(rc::gridStride({121, 161}, {61, 81}, s).ok());
  EXPECT_EQ(s, 2);
  const rc::RendererStatus bad = rc::gridStride({120, 160}, {50, 70}, s);
  EXPECT_EQ(bad.fault, rc::RendererFault::kGridSize);
  EXPECT_NE(bad.reason.find("70x50"), std::string::npos) << bad.reason;
}

TEST(RendererConversions, StrideTwoSetBecomesGridImageDepthAndFullK) {
  const Set set = makeSet(2);
  rc::RendererInput in;
  ASSERT_TRUE(
      rc::rendererInputFromMessages(set.image, set.depth, set.mask, set.info, true, in).ok());
  EXPECT_EQ(in.stride, 2);
  EXPECT_EQ(in.grid_size, (mm::ImageSize{6, 8}));
  EXPECT_DOUBLE_EQ(in.image_intrinsics.fx, 10.0);
  EXPECT_DOUBLE_EQ(in.image_intrinsics.cx, 8.0);
  EXPECT_DOUBLE_EQ(in.grid_intrinsics.cy, 3.0);
  ASSERT_EQ(in.grid_bgr.size(), cv::Size(8, 6));
  EXPECT_EQ(in.grid_bgr.at<cv::Vec3b>(2, 3), cv::Vec3b(6, 4, 7));  // image pixel (u 6, v 4)
  EXPECT_EQ(in.image_bgr.at<cv::Vec3b>(11, 15), cv::Vec3b(15, 11, 7));
  EXPECT_EQ(in.depth.at<float>(0, 0), 0.0f);  // NaN = no depth
  EXPECT_EQ(in.depth.at<float>(5, 7), 2.0f);
  EXPECT_EQ(in.kept.at<std::uint8_t>(5, 7), 255);

  // Without pixels: the checks and sizes only.
  rc::RendererInput light;
  ASSERT_TRUE(
      rc::rendererInputFromMessages(set.image, set.depth, set.mask, set.info, false, light).ok());
  EXPECT_TRUE(light.depth.empty());
  EXPECT_EQ(light.stride, 2);
}

TEST(RendererConversions, MillimetreDepth) {
  Set set = makeSet(1);
  set.depth.encoding = enc::TYPE_16UC1;
  set.depth.step = 16 * 2;
  set.depth.data.assign(12 * 16 * 2, 0);
  const std::uint16_t mm = 1500;
  std::memcpy(&set.depth.data[2], &mm, 2);
  rc::RendererInput in;
  ASSERT_TRUE(
      rc::rendererInputFromMessages(set.image, set.depth, set.mask, set.info, true, in).ok());
  EXPECT_FLOAT_EQ(in.depth.at<float>(0, 1), 1.5f);
  EXPECT_EQ(in.depth.at<float>(0, 0), 0.0f);
}

TEST(RendererConversions, EachBadInputHasItsFault) {
  using F = rc::RendererFault;
  Set s = makeSet(2);
  s.image.encoding = enc::YUV422;
  EXPECT_EQ(faultOf(s), F::kImageEncoding);
  s = makeSet(2);
  s.image.step = 10;
  EXPECT_EQ(faultOf(s), F::kImageStep);
  s = makeSet(2);
  s.depth.encoding = enc::TYPE_16SC1;
  EXPECT_EQ(faultOf(s), F::kDepthImage);
  s = makeSet(2);
  s.depth.data.resize(4);
  EXPECT_EQ(faultOf(s), F::kDepthImage);
  s = makeSet(2);
  s.mask.encoding = enc::RGB8;
  EXPECT_EQ(faultOf(s), F::kMaskImage);
  s = makeSet(2);
  s.mask.width = 4;
  s.mask.step = 4;
  EXPECT_EQ(faultOf(s), F::kMaskSize);
  s = makeSet(2);
  s.info.K.fill(0.0);
  EXPECT_EQ(faultOf(s), F::kCameraInfoIntrinsics);
  s = makeSet(2);
  s.info.width = 16;
  EXPECT_EQ(faultOf(s), F::kCameraInfoSize);
  s = makeSet(2);
  s.info.K[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(faultOf(s), F::kCameraInfoIntrinsics);
  s = makeSet(2);
  s.info.width = s.info.height = 0;
  EXPECT_EQ(faultOf(s), F::kCameraInfoSize);
  s = makeSet(2);
  s.depth.encoding = enc::RGB8;  // a colour image on the depth topic
  EXPECT_EQ(faultOf(s), F::kDepthImage);
  s = makeSet(2);
  s.depth.width = 0xFFFFFFFFu;  // "negative" width
  EXPECT_EQ(faultOf(s), F::kDepthImage);
  s = makeSet(2);
  s.image.width = 40;
  s.image.step = 120;
  s.image.data.resize(12 * 120);
  EXPECT_EQ(faultOf(s), F::kGridSize);
  EXPECT_STREQ(rc::toString(F::kTransformUnavailable), "transform_unavailable");
  EXPECT_STREQ(rc::toString(F::kMaskSize), "mask_size");
}

TEST(RendererConversions, OutputsAreRgb8Mono8AndNanHoles) {
  cv::Mat bgr(2, 3, CV_8UC3, cv::Scalar(1, 2, 3));
  cv::Mat mask = (cv::Mat_<std::uint8_t>(2, 3) << 255, 0, 255, 255, 255, 0);
  cv::Mat depth(2, 3, CV_32FC1, cv::Scalar(5.0f));
  std_msgs::Header header;
  header.frame_id = "cam";
  header.stamp = ros::Time(12, 34);
  const auto rgb = rc::rgbImageFromBgr(bgr, header);
  EXPECT_EQ(rgb->encoding, enc::RGB8);
  EXPECT_EQ(rgb->header.stamp, header.stamp);
  EXPECT_EQ(rgb->data[0], 3);
  EXPECT_EQ(rgb->data[2], 1);
  const auto m = rc::monoImage(mask, header);
  EXPECT_EQ(m->encoding, enc::MONO8);
  EXPECT_EQ(m->data[1], 0);
  EXPECT_EQ(m->data[0], 255);
  const auto d = rc::renderedDepthImage(depth, mask, header);
  float z[6];
  std::memcpy(z, d->data.data(), sizeof z);
  EXPECT_EQ(z[0], 5.0f);
  EXPECT_TRUE(std::isnan(z[1]));
  EXPECT_TRUE(std::isnan(z[5]));
  const auto info = rc::renderedCameraInfo({100, 110, 50, 40}, {704, 1280}, header);
  EXPECT_EQ(info->width, 1280u);
  EXPECT_EQ(info->height, 704u);
  EXPECT_DOUBLE_EQ(info->K[4], 110);
  EXPECT_DOUBLE_EQ(info->P[2], 50);
  EXPECT_DOUBLE_EQ(info->P[10], 1);
}
