// Unit tests of the ROS <-> core conversions and of the Config <-> params mapping; no master.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/ros/conversions.hpp"
#include "multimodal_nvs/ros/depth_color_images.hpp"
#include "multimodal_nvs/ros/depth_completion_config.hpp"
#include "multimodal_nvs/ros/input_timeline.hpp"
#include "multimodal_nvs/ros/recycled_message.hpp"
#include "multimodal_nvs/ros/stats_message.hpp"

namespace mm = multimodal_nvs;
namespace rc = multimodal_nvs::ros_conversions;
namespace enc = sensor_msgs::image_encodings;
using rc::InputFault;

namespace {

sensor_msgs::PointField field(const std::string& name, std::uint32_t offset, std::uint8_t type) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = type;
  f.count = 1;
  return f;
}

/// Cloud with x, y, z of type `type` after a 4-byte "intensity" field, `pad` extra bytes per point.
template <typename T>
sensor_msgs::PointCloud2 makeCloud(const std::vector<Eigen::Vector3d>& points, std::uint8_t type,
                                   std::uint32_t height = 1, std::uint32_t row_padding = 0) {
  sensor_msgs::PointCloud2 cloud;
  cloud.fields = {field("intensity", 0, sensor_msgs::PointField::FLOAT32),
                  field("z", 4 + 2 * sizeof(T), type), field("x", 4, type),
                  field("y", 4 + sizeof(T), type)};
  cloud.point_step = 4 + 3 * sizeof(T) + 3;
  cloud.height = height;
  cloud.width = points.size() / height;
  cloud.row_step = cloud.width * cloud.point_step + row_padding;
  cloud.data.assign(std::size_t(cloud.row_step) * height, 0xAB);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t row = i / cloud.width, col = i % cloud.width;
    std::uint8_t* record = &cloud.data[row * cloud.row_step + col * cloud.point_step];
    for (int axis = 0; axis < 3; ++axis) {
      const T value = static_cast<T>(points[i][axis]);
      std::memcpy(record + 4 + axis * sizeof(T), &value, sizeof(T));
    }
  }
  return cloud;
}

std::vector<Eigen::Vector3d> samplePoints() {
  return {{1, 2, 3}, {-4.5, 0.25, 10}, {0, 0, 1}, {7, -8, 9}, {0.5, 0.5, 0.5}, {3, 2, 1}};
}

InputFault cloudFault(const sensor_msgs::PointCloud2& cloud) {
  std::vector<Eigen::Vector3d> points;
  return rc::pointsFromCloud(cloud, Eigen::Isometry3d::Identity(), points, nullptr).fault;
}

TEST(CloudConversion, ReadsFloat32AndFloat64WithAnyOffsetsAndRowPadding) {
  const auto expected = samplePoints();
  for (const auto& cloud : {makeCloud<float>(expected, sensor_msgs::PointField::FLOAT32),
                            makeCloud<double>(expected, sensor_msgs::PointField::FLOAT64, 2, 5)}) {
    std::vector<Eigen::Vector3d> points;
    std::size_t non_finite = 99;
    const auto status =
        rc::pointsFromCloud(cloud, Eigen::Isometry3d::Identity(), points, &non_finite);
    ASSERT_TRUE(status.ok()) << status.reason;
    ASSERT_EQ(points.size(), expected.size());
    EXPECT_EQ(non_finite, 0u);
    for (std::size_t i = 0; i < points.size(); ++i)
      EXPECT_TRUE(points[i].isApprox(expected[i]));
  }
}

TEST(CloudConversion, AppliesTheTransformInDouble) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(0.1, -0.2, 0.3);
  const auto expected = samplePoints();
  std::vector<Eigen::Vector3d> points;
  ASSERT_TRUE(rc::pointsFromCloud(makeCloud<double>(expected, sensor_msgs::PointField::FLOAT64), t,
                                  points, nullptr)
                  .ok());
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR((points[i] - t * expected[i]).norm(), 0.0, 1e-12);
  }
}

TEST(CloudConversion, SkipsNonFinitePointsAndRejectsAllNonFinite) {
  auto pts = samplePoints();
  pts[1].x() = std::numeric_limits<double>::quiet_NaN();
  pts[3].z() = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3d> points;
  std::size_t non_finite = 0;
  ASSERT_TRUE(rc::pointsFromCloud(makeCloud<float>(pts, sensor_msgs::PointField::FLOAT32),
                                  Eigen::Isometry3d::Identity(), points, &non_finite)
                  .ok());
  EXPECT_EQ(points.size(), 4u);
  EXPECT_EQ(non_finite, 2u);
  for (auto& p : pts)
    p.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(cloudFault(makeCloud<float>(pts, sensor_msgs::PointField::FLOAT32)),
            InputFault::kCloudNoFinitePoint);
}

TEST(CloudConversion, RejectsEveryMalformedLayoutWithItsReason) {
  const auto good = makeCloud<float>(samplePoints(), sensor_msgs::PointField::FLOAT32);
  ASSERT_EQ(cloudFault(good), InputFault::kNone);
  auto broken = [&](const std::function<void(sensor_msgs::PointCloud2&)>& edit) {
    sensor_msgs::PointCloud2 cloud = good;
    edit(cloud);
    return cloudFault(cloud);
  };
  EXPECT_EQ(broken([](auto& c) { c.fields.erase(c.fields.begin() + 1); }),
            InputFault::kCloudMissingField);  // no z
  EXPECT_EQ(broken([](auto& c) { c.fields[2].name = "X"; }), InputFault::kCloudMissingField);
  EXPECT_EQ(broken([](auto& c) { c.fields[2].datatype = sensor_msgs::PointField::INT32; }),
            InputFault::kCloudFieldDatatype);
  EXPECT_EQ(broken([](auto& c) { c.fields[3].datatype = sensor_msgs::PointField::UINT8; }),
            InputFault::kCloudFieldDatatype);
  EXPECT_EQ(broken([](auto& c) { c.fields[1].count = 3; }), InputFault::kCloudFieldCount);
  EXPECT_EQ(broken([](auto& c) { c.fields[1].count = 0; }), InputFault::kCloudFieldCount);
  EXPECT_EQ(broken([](auto& c) { c.fields[1].offset = c.point_step - 3; }),
            InputFault::kCloudFieldOffset);
  EXPECT_EQ(
      broken([](auto& c) { c.fields[2].offset = 0xFFFFFFFF; }),  // offset + 4 wraps in 32 bits
      InputFault::kCloudFieldOffset);
  EXPECT_EQ(broken([](auto& c) { c.point_step = 0; }), InputFault::kCloudFieldOffset);
  EXPECT_EQ(broken([](auto& c) { c.fields[1].datatype = sensor_msgs::PointField::FLOAT64; }),
            InputFault::kCloudFieldOffset);  // z as double at offset 12 runs past point_step 19
  EXPECT_EQ(broken([](auto& c) { c.data.pop_back(); }), InputFault::kCloudDataTooShort);
  EXPECT_EQ(broken([](auto& c) { c.height = 2; }), InputFault::kCloudDataTooShort);
  EXPECT_EQ(broken([](auto& c) { c.row_step -= 1; }), InputFault::kCloudLayout);
  EXPECT_EQ(broken([](auto& c) { c.is_bigendian = true; }), InputFault::kCloudBigEndian);
  EXPECT_EQ(broken([](auto& c) { c.width = 0; }), InputFault::kCloudEmpty);
  EXPECT_EQ(broken([](auto& c) { c.height = 0; }), InputFault::kCloudEmpty);
  // width * height and row_step * height do not wrap around in 32 bits.
  EXPECT_EQ(broken([](auto& c) {
              c.width = 0x10000;
              c.height = 0x10000;
              c.row_step = c.width * c.point_step;
            }),
            InputFault::kCloudDataTooShort);
  EXPECT_EQ(broken([](auto& c) {
              c.width = 0xFFFFFFFF;
              c.row_step = 0xFFFFFFFF;
            }),
            InputFault::kCloudLayout);
}

TEST(CloudConversion, HugeCloudsAreReadEveryKthPoint) {
  std::vector<Eigen::Vector3d> many;
  for (int i = 0; i < 1000; ++i)
    many.emplace_back(i, 0.0, 1.0);
  const auto cloud = makeCloud<float>(many, sensor_msgs::PointField::FLOAT32, 10);
  std::vector<Eigen::Vector3d> points;
  std::size_t step = 0;
  ASSERT_TRUE(
      rc::pointsFromCloud(cloud, Eigen::Isometry3d::Identity(), 300, points, nullptr, &step).ok());
  EXPECT_EQ(step, 4u);  // ceil(1000 / 300)
  ASSERT_EQ(points.size(), 250u);
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_EQ(points[i].x(), 4.0 * i);  // across the rows of the organised cloud
  ASSERT_TRUE(
      rc::pointsFromCloud(cloud, Eigen::Isometry3d::Identity(), 1000, points, nullptr, &step).ok());
  EXPECT_EQ(step, 1u);
  EXPECT_EQ(points.size(), 1000u);
}

TEST(CloudConversion, RejectsACloudEntirelyBehindTheCamera) {
  std::vector<Eigen::Vector3d> points = {{1, 2, -3}, {0, 0, 0}, {4, 5, -0.1}};
  EXPECT_EQ(rc::checkPointsInFront(points).fault, InputFault::kCloudBehindCamera);
  points.emplace_back(0, 0, 0.01);
  EXPECT_TRUE(rc::checkPointsInFront(points).ok());
  EXPECT_STREQ(rc::toString(InputFault::kCloudBehindCamera), "cloud_behind_camera");
}

TEST(InputTimeline, DuplicatesAndReorderedStampsAreNotNewerALongJumpIsARestart) {
  mm::StampOrder order(ros::Duration(1.0));
  using V = mm::StampOrder::Verdict;
  EXPECT_EQ(order.check(ros::Time(100.0)), V::kNewer);
  EXPECT_EQ(order.check(ros::Time(100.0)), V::kNotNewer);  // duplicate
  EXPECT_EQ(order.check(ros::Time(99.5)), V::kNotNewer);   // reordered
  EXPECT_EQ(order.check(ros::Time(100.1)), V::kNewer);
  EXPECT_EQ(order.check(ros::Time(40.0)), V::kRestart);  // a replayed bag
  EXPECT_EQ(order.last(), ros::Time(40.0));
  EXPECT_EQ(order.check(ros::Time(40.1)), V::kNewer);
  order.reset();
  EXPECT_EQ(order.check(ros::Time(1.0)), V::kNewer);

  mm::ClockWatch clock;
  ros::Duration jump;
  EXPECT_FALSE(clock.jumpedBack(ros::Time(10.0), &jump));
  EXPECT_FALSE(clock.jumpedBack(ros::Time(10.0), &jump));
  EXPECT_FALSE(clock.jumpedBack(ros::Time(11.0), &jump));
  EXPECT_TRUE(clock.jumpedBack(ros::Time(2.0), &jump));
  EXPECT_DOUBLE_EQ(jump.toSec(), 9.0);
  EXPECT_FALSE(clock.jumpedBack(ros::Time(2.5), &jump));
}

TEST(InputTimeline, AClockJumpForgetsTheStampsAStampRestartIsReportedALateStampIsAFault) {
  mm::InputTimeline timeline;
  EXPECT_FALSE(timeline.clockJumpedBack(ros::Time(50.0)));
  auto admission = timeline.admit(ros::Time(100.0));
  EXPECT_TRUE(admission.status.ok());
  EXPECT_FALSE(admission.restarted);

  admission = timeline.admit(ros::Time(100.0));
  EXPECT_EQ(admission.status.fault, InputFault::kStampNotNewer);
  EXPECT_NE(admission.status.reason.find("repeats"), std::string::npos);
  admission = timeline.admit(ros::Time(99.5));
  EXPECT_NE(admission.status.reason.find("precedes"), std::string::npos);

  admission = timeline.admit(ros::Time(40.0));  // a bag replayed without --clock
  EXPECT_TRUE(admission.restarted);
  EXPECT_DOUBLE_EQ(admission.back.toSec(), 60.0);
  EXPECT_TRUE(admission.status.ok());
  EXPECT_EQ(timeline.admit(ros::Time(40.0)).status.fault, InputFault::kStampNotNewer);

  ros::Duration jump;
  EXPECT_TRUE(timeline.clockJumpedBack(ros::Time(10.0), &jump));  // a bag replayed with --clock
  EXPECT_DOUBLE_EQ(jump.toSec(), 40.0);
  admission = timeline.admit(ros::Time(5.0));  // the new run's first set: no history left
  EXPECT_TRUE(admission.status.ok());
  EXPECT_FALSE(admission.restarted);
}

TEST(CloudConversion, FloatOverloadMatches) {
  std::vector<Eigen::Vector3f> points;
  ASSERT_TRUE(rc::pointsFromCloud(
                  makeCloud<float>(samplePoints(), sensor_msgs::PointField::FLOAT32), points)
                  .ok());
  EXPECT_EQ(points.size(), samplePoints().size());
  EXPECT_FLOAT_EQ(points[1].x(), -4.5f);
}

sensor_msgs::Image makeImage(const std::string& encoding, int channels, int width, int height,
                             int padding) {
  sensor_msgs::Image image;
  image.encoding = encoding;
  image.width = width;
  image.height = height;
  image.step = width * channels + padding;
  image.data.assign(std::size_t(image.step) * height, 0);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      for (int ch = 0; ch < channels; ++ch) {
        image.data[v * image.step + u * channels + ch] = std::uint8_t(10 * ch + u + 3 * v);
      }
    }
  }
  return image;
}

TEST(ImageConversion, EveryEncodingGivesRgbAndBgrHonouringStep) {
  struct Case {
    std::string encoding;
    int channels;
    int r, g, b;  // channel index holding R, G, B
  };
  for (const Case& c : std::vector<Case>{{enc::RGB8, 3, 0, 1, 2},
                                         {enc::BGR8, 3, 2, 1, 0},
                                         {enc::RGBA8, 4, 0, 1, 2},
                                         {enc::BGRA8, 4, 2, 1, 0},
                                         {enc::MONO8, 1, 0, 0, 0}}) {
    const sensor_msgs::Image image = makeImage(c.encoding, c.channels, 7, 5, 3);
    cv::Mat rgb, bgr;
    ASSERT_TRUE(rc::colourFromImage(image, rc::ChannelOrder::kRgb, rgb).ok()) << c.encoding;
    ASSERT_TRUE(rc::colourFromImage(image, rc::ChannelOrder::kBgr, bgr).ok()) << c.encoding;
    for (const cv::Mat* out : {&rgb, &bgr}) {
      ASSERT_EQ(out->type(), CV_8UC3);
      ASSERT_EQ(out->rows, 5);
      ASSERT_EQ(out->cols, 7);
    }
    for (int v = 0; v < 5; ++v) {
      for (int u = 0; u < 7; ++u) {
        const cv::Vec3b px = rgb.at<cv::Vec3b>(v, u), bgr_px = bgr.at<cv::Vec3b>(v, u);
        const std::uint8_t* in = &image.data[v * image.step + u * c.channels];
        ASSERT_EQ(px[0], in[c.r]) << c.encoding;
        ASSERT_EQ(px[1], in[c.g]) << c.encoding;
        ASSERT_EQ(px[2], in[c.b]) << c.encoding;
        ASSERT_EQ(bgr_px[0], in[c.b]) << c.encoding;
        ASSERT_EQ(bgr_px[1], in[c.g]) << c.encoding;
        ASSERT_EQ(bgr_px[2], in[c.r]) << c.encoding;
      }
    }
  }
}

TEST(ImageConversion, AnEncodingInTheAskedOrderIsWrappedWithoutCopy) {
  const sensor_msgs::Image image = makeImage(enc::RGB8, 3, 4, 3, 2);
  cv::Mat rgb;
  ASSERT_TRUE(rc::colourFromImage(image, rc::ChannelOrder::kRgb, rgb).ok());
  EXPECT_EQ(rgb.data, image.data.data());
  EXPECT_EQ(rgb.step[0], image.step);
  const sensor_msgs::Image bgr8 = makeImage(enc::BGR8, 3, 4, 3, 2);
  cv::Mat bgr;
  ASSERT_TRUE(rc::colourFromImage(bgr8, rc::ChannelOrder::kBgr, bgr).ok());
  EXPECT_EQ(bgr.data, bgr8.data.data());
  EXPECT_EQ(bgr.step[0], bgr8.step);
}

TEST(ImageConversion, RejectsBadEncodingStepAndSize) {
  sensor_msgs::Image image = makeImage(enc::BGR8, 3, 4, 3, 0);
  cv::Mat rgb;
  image.encoding = enc::TYPE_16UC1;
  EXPECT_EQ(rc::colourFromImage(image, rc::ChannelOrder::kRgb, rgb).fault,
            InputFault::kImageEncoding);
  image.encoding = "bayer_rggb8";
  EXPECT_EQ(rc::validateImage(image).fault, InputFault::kImageEncoding);
  image.encoding = enc::BGR8;
  image.step = 11;
  EXPECT_EQ(rc::colourFromImage(image, rc::ChannelOrder::kRgb, rgb).fault, InputFault::kImageStep);
  image.step = 12;
  image.data.pop_back();
  EXPECT_EQ(rc::colourFromImage(image, rc::ChannelOrder::kRgb, rgb).fault, InputFault::kImageStep);
  image.width = 0;
  EXPECT_EQ(rc::validateImage(image).fault, InputFault::kImageEmpty);
}

TEST(ImageConversion, DecodesPngAndJpegAndRejectsGarbage) {
  cv::Mat bgr(6, 8, CV_8UC3, cv::Scalar(10, 120, 240));  // B, G, R
  for (const char* ext : {".png", ".jpg"}) {
    std::vector<std::uint8_t> bytes;
    ASSERT_TRUE(cv::imencode(ext, bgr, bytes));
    sensor_msgs::CompressedImage msg;
    msg.format = ext;
    msg.data = bytes;
    cv::Mat decoded;
    ASSERT_TRUE(rc::bgrFromCompressed(msg, decoded).ok()) << ext;
    ASSERT_EQ(decoded.size(), bgr.size());
    EXPECT_NEAR(decoded.at<cv::Vec3b>(2, 3)[2], 240, 3) << ext;  // R
    EXPECT_NEAR(decoded.at<cv::Vec3b>(2, 3)[0], 10, 3) << ext;   // B
  }
  sensor_msgs::CompressedImage garbage;
  garbage.format = "jpeg";
  garbage.data = {1, 2, 3, 4};
  cv::Mat decoded;
  EXPECT_EQ(rc::bgrFromCompressed(garbage, decoded).fault, InputFault::kImageDecode);
  garbage.data.clear();
  EXPECT_EQ(rc::bgrFromCompressed(garbage, decoded).fault, InputFault::kImageDecode);
}

TEST(FrameImage, RawIsValidatedAndConvertedOnlyOnDemand) {
  sensor_msgs::Image image = makeImage(enc::RGB8, 3, 4, 3, 2);
  image.header.frame_id = "camera";
  rc::FrameImage frame;
  ASSERT_TRUE(rc::frameImage(image, frame).ok());
  EXPECT_EQ(frame.header.frame_id, "camera");
  EXPECT_EQ(frame.size, (mm::ImageSize{3, 4}));
  cv::Mat rgb, bgr;
  ASSERT_TRUE(frame.rgb(rgb).ok());
  EXPECT_EQ(rgb.data, image.data.data());  // rgb8: the message's own pixels
  ASSERT_TRUE(frame.bgr(bgr).ok());        // and swapped for the depth models
  EXPECT_NE(bgr.data, image.data.data());
  EXPECT_EQ(bgr.at<cv::Vec3b>(1, 2)[0], rgb.at<cv::Vec3b>(1, 2)[2]);
  EXPECT_EQ(bgr.at<cv::Vec3b>(1, 2)[2], rgb.at<cv::Vec3b>(1, 2)[0]);
  image.encoding = enc::TYPE_16UC1;
  EXPECT_EQ(rc::frameImage(image, frame).fault, InputFault::kImageEncoding);
}

TEST(FrameImage, CompressedIsDecodedAtOnce) {
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 120, 240)), bytes));
  sensor_msgs::CompressedImage msg;
  msg.format = "png";
  msg.data = bytes;
  rc::FrameImage frame;
  ASSERT_TRUE(rc::frameImage(msg, frame).ok());
  EXPECT_EQ(frame.size, (mm::ImageSize{6, 8}));
  msg.data.clear();  // the decoded pixels do not depend on the message any more
  cv::Mat rgb, bgr;
  ASSERT_TRUE(frame.rgb(rgb).ok());
  EXPECT_EQ(rgb.at<cv::Vec3b>(2, 3), cv::Vec3b(240, 120, 10));
  ASSERT_TRUE(frame.bgr(bgr).ok());
  EXPECT_EQ(bgr.at<cv::Vec3b>(2, 3), cv::Vec3b(10, 120, 240));
  EXPECT_EQ(rc::frameImage(msg, frame).fault, InputFault::kImageDecode);
}

TEST(StatsMessage, CarriesTheCoreStatsTheGroundPlaneAndTheLatency) {
  mm::DepthMapStats stats;
  stats.points_total = 1234;
  stats.points_in_view = 1000;
  stats.neighbour_sets = 77;
  stats.kept = 4321;
  stats.compute_ms = 12.5;
  stats.ground_source = "returns";
  stats.ground_mode = "dense";
  stats.ground_inlier_fraction = 0.625;
  stats.ground_scan_line_share = 0.75;
  stats.ground_hidden_returns = 1202;
  stats.ground_edge_ratio = 0.24;
  stats.ground_single_scan_plane = true;
  stats.ground_camera_height = 1.62;
  stats.ground_pitch_deg = -0.45;
  stats.ground_roll_deg = 1.5;
  stats.guided_return_density = 0.093;
  stats.guided_prior_weight = 0.00093;
  stats.guided_band_top_deg = 2.75;
  std_msgs::Header header;
  header.stamp = ros::Time(5.0);
  header.frame_id = "camera";
  const auto message = rc::statsMessage(stats, header, 20.25);
  EXPECT_EQ(message->header.stamp, header.stamp);
  EXPECT_EQ(message->header.frame_id, "camera");
  EXPECT_EQ(message->points_in, 1234u);
  EXPECT_EQ(message->points_in_view, 1000u);
  EXPECT_EQ(message->neighbour_sets, 77u);
  EXPECT_EQ(message->kept_pixels, 4321u);
  EXPECT_FLOAT_EQ(message->compute_ms, 12.5f);
  EXPECT_FLOAT_EQ(message->latency_ms, 20.25f);
  EXPECT_EQ(message->ground_source, "returns");
  EXPECT_EQ(message->ground_mode, "dense");
  EXPECT_FLOAT_EQ(message->ground_inlier_fraction, 0.625f);
  EXPECT_FLOAT_EQ(message->ground_scan_line_share, 0.75f);
  EXPECT_EQ(message->ground_hidden_returns, 1202);
  EXPECT_FLOAT_EQ(message->ground_edge_ratio, 0.24f);
  EXPECT_TRUE(message->ground_single_scan_plane);
  EXPECT_FLOAT_EQ(message->ground_camera_height, 1.62f);
  EXPECT_FLOAT_EQ(message->ground_pitch_deg, -0.45f);
  EXPECT_FLOAT_EQ(message->ground_roll_deg, 1.5f);
  EXPECT_FLOAT_EQ(message->guided_return_density, 0.093f);
  EXPECT_FLOAT_EQ(message->guided_prior_weight, 0.00093f);
  EXPECT_FLOAT_EQ(message->guided_band_top_deg, 2.75f);
}

TEST(StatsMessage, TheGroundPlanePolygonIsTheRoadOfTheStatsInTheImagesFrame) {
  mm::DepthMapStats stats;
  std_msgs::Header header;
  header.stamp = ros::Time(7.0);
  header.frame_id = "camera_optical";
  EXPECT_FALSE(rc::groundPlanePolygon(stats, header));  // a model without a ground plane
  stats.ground_camera_height = 1.3;
  const auto level = rc::groundPlanePolygon(stats, header);
  ASSERT_TRUE(level);
  EXPECT_EQ(level->header.frame_id, "camera_optical");
  EXPECT_EQ(level->header.stamp, header.stamp);
  ASSERT_EQ(level->polygon.points.size(), 4u);
  for (const auto& p : level->polygon.points)
    EXPECT_FLOAT_EQ(p.y, 1.3f);  // 1.3 m below a level camera (y down)
  EXPECT_FLOAT_EQ(level->polygon.points[0].z, 2.5f);
  EXPECT_FLOAT_EQ(level->polygon.points[2].z, 40.5f);
  EXPECT_FLOAT_EQ(level->polygon.points[0].x, -9.5f);
  // Pitched up: the road falls away below the optical axis with the distance.
  stats.ground_pitch_deg = 6.8;
  const auto pitched = rc::groundPlanePolygon(stats, header);
  ASSERT_TRUE(pitched);
  EXPECT_GT(pitched->polygon.points[2].y, pitched->polygon.points[1].y);
}

TEST(StatsMessage, ModelsWithoutAGroundPlaneSayNoneRan) {
  const auto message = rc::statsMessage(mm::DepthMapStats{}, std_msgs::Header{}, 1.0);
  EXPECT_EQ(message->ground_source, "");
  EXPECT_EQ(message->ground_mode, "");
  EXPECT_FLOAT_EQ(message->ground_scan_line_share, -1.0f);
  EXPECT_EQ(message->ground_hidden_returns, -1);
  EXPECT_FLOAT_EQ(message->ground_edge_ratio, -1.0f);
  EXPECT_FALSE(message->ground_single_scan_plane);
  EXPECT_FLOAT_EQ(message->ground_camera_height, -1.0f);
  EXPECT_FLOAT_EQ(message->guided_return_density, -1.0f);
  EXPECT_FLOAT_EQ(message->guided_prior_weight, -1.0f);
  EXPECT_TRUE(std::isnan(message->guided_band_top_deg));
}

sensor_msgs::CameraInfo makeInfo() {
  sensor_msgs::CameraInfo info;
  info.width = 320;
  info.height = 240;
  info.K = {200, 0, 160, 0, 210, 120, 0, 0, 1};
  info.P = {200, 0, 160, -20, 0, 210, 120, 0, 0, 0, 1, 0};
  return info;
}

TEST(CameraInfoConversion, ReadsKAndChecksSize) {
  mm::PinholeIntrinsics k;
  ASSERT_TRUE(rc::intrinsicsFromCameraInfo(makeInfo(), mm::ImageSize{240, 320}, k).ok());
  EXPECT_EQ(k.fx, 200);
  EXPECT_EQ(k.fy, 210);
  EXPECT_EQ(k.cx, 160);
  EXPECT_EQ(k.cy, 120);
  EXPECT_EQ(rc::intrinsicsFromCameraInfo(makeInfo(), mm::ImageSize{240, 321}, k).fault,
            InputFault::kCameraInfoSize);
  sensor_msgs::CameraInfo zero = makeInfo();
  zero.K.fill(0.0);
  EXPECT_EQ(rc::intrinsicsFromCameraInfo(zero, mm::ImageSize{240, 320}, k).fault,
            InputFault::kCameraInfoIntrinsics);
  sensor_msgs::CameraInfo nan = makeInfo();
  nan.K[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(rc::intrinsicsFromCameraInfo(nan, mm::ImageSize{240, 320}, k).fault,
            InputFault::kCameraInfoIntrinsics);
  sensor_msgs::CameraInfo binned = makeInfo();
  binned.binning_x = 2;
  EXPECT_EQ(rc::intrinsicsFromCameraInfo(binned, mm::ImageSize{240, 320}, k).fault,
            InputFault::kCameraInfoIntrinsics);
}

TEST(CameraInfoConversion, ReadsTheLensModelOrNamesTheUnsupportedOne) {
  mm::PinholeIntrinsics k;
  sensor_msgs::CameraInfo plumb = makeInfo();
  plumb.distortion_model = "plumb_bob";
  plumb.D = {-0.1, 0.14, -0.004, -0.005, 0.0};
  ASSERT_TRUE(rc::intrinsicsFromCameraInfo(plumb, mm::ImageSize{240, 320}, k).ok());
  EXPECT_EQ(k.distortion.model, mm::LensDistortion::Model::kPlumbBob);
  EXPECT_EQ(k.distortion.coefficients[1], 0.14);
  sensor_msgs::CameraInfo rational = makeInfo();
  rational.distortion_model = "rational_polynomial";
  rational.D = {0.8, 0.15, 0.001, -0.002, 0.003, 1.1, 0.35, 0.02};
  ASSERT_TRUE(rc::intrinsicsFromCameraInfo(rational, mm::ImageSize{240, 320}, k).ok());
  EXPECT_EQ(k.distortion.model, mm::LensDistortion::Model::kRationalPolynomial);
  sensor_msgs::CameraInfo zeros = makeInfo();
  zeros.distortion_model = "plumb_bob";
  zeros.D.assign(5, 0.0);
  ASSERT_TRUE(rc::intrinsicsFromCameraInfo(zeros, mm::ImageSize{240, 320}, k).ok());
  EXPECT_FALSE(k.distortion.any());  // the pinhole path, unchanged
  sensor_msgs::CameraInfo fisheye = makeInfo();
  fisheye.distortion_model = "equidistant";
  fisheye.D = {0.1, 0.01, 0.0, 0.0};
  const rc::ConversionStatus status =
      rc::intrinsicsFromCameraInfo(fisheye, mm::ImageSize{240, 320}, k);
  EXPECT_EQ(status.fault, InputFault::kCameraInfoDistortion);
  EXPECT_NE(status.reason.find("'equidistant' is not supported"), std::string::npos)
      << status.reason;
  EXPECT_STREQ(rc::toString(InputFault::kCameraInfoDistortion), "camera_info_distortion");
  sensor_msgs::CameraInfo short_d = plumb;
  short_d.D.pop_back();
  EXPECT_EQ(rc::intrinsicsFromCameraInfo(short_d, mm::ImageSize{240, 320}, k).fault,
            InputFault::kCameraInfoDistortion);
}

mm::DepthMap makeDepthMap();

TEST(OutputConversion, ColoredCloudOfADistortedCameraUsesTheUndistortedRays) {
  const mm::DepthMap map = makeDepthMap();
  const mm::PinholeIntrinsics k{
      100, 120, 3, 2, mm::LensDistortion::fromRos("plumb_bob", {-0.2, 0.05, 0, 0, 0}, "t")};
  std_msgs::Header header;
  sensor_msgs::PointCloud2 cloud;
  rc::coloredCloud(map, k, cv::Mat(), 1, header, cloud);
  std::vector<Eigen::Vector3f> points;
  ASSERT_TRUE(rc::pointsFromCloud(cloud, points).ok());
  std::size_t i = 0;
  for (int r = 0; r < map.grid.rows(); ++r) {
    for (int c = 0; c < map.grid.cols(); ++c) {
      if (!map.valid[r * map.grid.cols() + c]) continue;
      ASSERT_LT(i, points.size());
      double u = 0, v = 0;
      ASSERT_TRUE(k.project(points[i].x(), points[i].y(), points[i].z(), &u, &v));
      EXPECT_NEAR(u, c * 2, 1e-3);  // back to the pixel through the lens
      EXPECT_NEAR(v, r * 2, 1e-3);
      ++i;
    }
  }
  EXPECT_EQ(i, points.size());
}

mm::DepthMap makeDepthMap() {
  mm::DepthMap map;
  map.grid = mm::StrideGrid{mm::ImageSize{5, 7}, 2};  // 3 x 4 grid
  const std::size_t n = map.grid.size();
  map.depth.resize(n);
  map.variance.resize(n);
  map.valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    map.valid[i] = i % 3 != 0;
    map.depth[i] = map.valid[i] ? 2.0f + i : -1.0f;
    map.variance[i] = i == 5 ? std::numeric_limits<float>::infinity() : 0.5f * i;
  }
  return map;
}

float floatAt(const sensor_msgs::Image& image, std::size_t i) {
  float value;
  std::memcpy(&value, &image.data[4 * i], 4);
  return value;
}

TEST(OutputConversion, DepthVarianceAndMaskImages) {
  const mm::DepthMap map = makeDepthMap();
  std_msgs::Header header;
  header.frame_id = "cam";
  header.stamp = ros::Time(12, 34);
  const auto depth = boost::make_shared<sensor_msgs::Image>();
  const auto variance = boost::make_shared<sensor_msgs::Image>();
  const auto mask = boost::make_shared<sensor_msgs::Image>();
  rc::depthImage(map, header, *depth);
  rc::varianceImage(map, header, *variance);
  rc::maskImage(map, header, *mask);
  for (const auto& image : {depth, variance, mask}) {
    EXPECT_EQ(image->header.frame_id, "cam");
    EXPECT_EQ(image->header.stamp, header.stamp);
    EXPECT_EQ(image->height, 3u);
    EXPECT_EQ(image->width, 4u);
  }
  EXPECT_EQ(depth->encoding, enc::TYPE_32FC1);
  EXPECT_EQ(depth->step, 16u);
  EXPECT_EQ(mask->encoding, enc::MONO8);
  for (std::size_t i = 0; i < map.depth.size(); ++i) {
    if (map.valid[i]) {
      EXPECT_EQ(floatAt(*depth, i), map.depth[i]);
      EXPECT_EQ(mask->data[i], 255);
    } else {
      EXPECT_TRUE(std::isnan(floatAt(*depth, i)));
      EXPECT_EQ(mask->data[i], 0);
    }
    EXPECT_EQ(floatAt(*variance, i), map.variance[i]);
  }
}

TEST(OutputConversion, RecycledImageIsRewrittenAndAHugeBufferGivenBack) {
  mm::DepthMap map = makeDepthMap();
  std_msgs::Header header;
  sensor_msgs::Image image;
  rc::depthImage(map, header, image);
  const std::uint8_t* const buffer = image.data.data();
  map.valid.assign(map.valid.size(), 1);  // every pixel kept now
  rc::depthImage(map, header, image);
  EXPECT_EQ(image.data.data(), buffer);  // same size: the buffer is reused
  for (std::size_t i = 0; i < map.depth.size(); ++i)
    EXPECT_EQ(floatAt(image, i), map.depth[i]);
  // After a huge frame the next usual one must not keep the huge buffer.
  image.data.resize(64u << 20);
  rc::maskImage(map, header, image);
  EXPECT_EQ(image.data.size(), map.valid.size());
  EXPECT_LT(image.data.capacity(), 1u << 20);
  EXPECT_EQ(image.encoding, enc::MONO8);
  EXPECT_EQ(image.step, 4u);
}

TEST(RecycledMessage, HandsOutAMessageAgainOnlyWhenNobodyElseHoldsIt) {
  mm::RecycledMessage<sensor_msgs::Image> recycled;
  const sensor_msgs::Image* const first = recycled.next().get();
  EXPECT_EQ(recycled.next().get(), first);                  // published and released: written again
  const sensor_msgs::ImageConstPtr held = recycled.next();  // an in-process subscriber keeps it
  const sensor_msgs::ImagePtr fresh = recycled.next();
  EXPECT_NE(fresh.get(), held.get());
  EXPECT_EQ(held.get(), first);
  EXPECT_NE(recycled.next().get(), fresh.get());  // `fresh` is still held, by this test
}

TEST(OutputConversion, GridCameraInfoScalesByStride) {
  const auto info = rc::gridCameraInfo(makeInfo(), mm::StrideGrid{mm::ImageSize{240, 320}, 4});
  EXPECT_EQ(info->width, 80u);
  EXPECT_EQ(info->height, 60u);
  EXPECT_DOUBLE_EQ(info->K[0], 50);
  EXPECT_DOUBLE_EQ(info->K[2], 40);
  EXPECT_DOUBLE_EQ(info->K[4], 52.5);
  EXPECT_DOUBLE_EQ(info->K[5], 30);
  EXPECT_DOUBLE_EQ(info->K[8], 1);
  EXPECT_DOUBLE_EQ(info->P[3], -5);
  EXPECT_DOUBLE_EQ(info->P[10], 1);
}

TEST(OutputConversion, ColoredCloudBackProjectsKeptPixelsWithTheirColour) {
  const mm::DepthMap map = makeDepthMap();
  const mm::PinholeIntrinsics k{100, 120, 3, 2};
  cv::Mat rgb(5, 7, CV_8UC3);
  for (int v = 0; v < 5; ++v) {
    for (int u = 0; u < 7; ++u)
      rgb.at<cv::Vec3b>(v, u) = cv::Vec3b(u * 30, v * 40, 7);
  }
  std_msgs::Header header;
  header.frame_id = "cam";
  // One message for both: the second fill rewrites a message that held a larger cloud, as a
  // recycled output does.
  const auto cloud = boost::make_shared<sensor_msgs::PointCloud2>();
  for (int cloud_stride : {1, 2}) {
    rc::coloredCloud(map, k, rgb, cloud_stride, header, *cloud);
    EXPECT_EQ(cloud->header.frame_id, "cam");
    std::vector<Eigen::Vector3f> points;
    ASSERT_TRUE(rc::pointsFromCloud(*cloud, points).ok());
    std::size_t expected_count = 0, i = 0;
    for (int r = 0; r < map.grid.rows(); r += cloud_stride) {
      for (int c = 0; c < map.grid.cols(); c += cloud_stride) {
        const std::size_t index = r * map.grid.cols() + c;
        if (!map.valid[index]) continue;
        ++expected_count;
        const int u = c * 2, v = r * 2;
        const float z = map.depth[index];
        ASSERT_LT(i, points.size());
        EXPECT_NEAR(points[i].x(), (u - k.cx) * z / k.fx, 1e-5);
        EXPECT_NEAR(points[i].y(), (v - k.cy) * z / k.fy, 1e-5);
        EXPECT_EQ(points[i].z(), z);
        std::uint32_t packed;
        std::memcpy(&packed, &cloud->data[i * cloud->point_step + 12], 4);
        const cv::Vec3b px = rgb.at<cv::Vec3b>(v, u);
        EXPECT_EQ(packed, (std::uint32_t(px[0]) << 16) | (std::uint32_t(px[1]) << 8) | px[2]);
        float stddev;
        std::memcpy(&stddev, &cloud->data[i * cloud->point_step + 16], 4);
        EXPECT_FLOAT_EQ(stddev, std::sqrt(map.variance[index]));
        ++i;
      }
    }
    EXPECT_EQ(cloud->width, expected_count);
    EXPECT_EQ(cloud->row_step, cloud->width * cloud->point_step);
  }
}

TEST(OutputConversion, ColoredCloudOnAPoolWritesTheSameBytes) {
  // A grid with an irregular mask (rows of every kept count, some empty), pinhole and through a
  // lens: the rows written in parallel land where the serial pass puts them.
  mm::DepthMap map;
  map.grid = mm::StrideGrid{{61, 97}, 1};
  const std::size_t n = std::size_t(map.grid.size());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> depth(0.5f, 80.0f), variance(0.01f, 9.0f);
  map.depth.resize(n);
  map.variance.resize(n);
  map.valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    map.depth[i] = depth(rng);
    map.variance[i] = variance(rng);
    const int r = static_cast<int>(i / 97);
    map.valid[i] = r % 7 != 3 && rng() % (1 + r % 5) == 0;
  }
  cv::Mat rgb(61, 97, CV_8UC3);
  cv::randu(rgb, cv::Scalar::all(0), cv::Scalar::all(255));
  mm::PinholeIntrinsics pinhole{80, 80, 48, 30};
  mm::PinholeIntrinsics lens = pinhole;
  lens.distortion =
      mm::LensDistortion::fromRos("plumb_bob", {-0.2, 0.05, 0.001, -0.001, 0.0}, "test");
  ASSERT_TRUE(lens.distortion.any());
  for (const mm::PinholeIntrinsics& k : {pinhole, lens}) {
    for (int cloud_stride : {1, 2, 3}) {
      sensor_msgs::PointCloud2 serial;
      rc::coloredCloud(map, k, rgb, cloud_stride, {}, serial);
      ASSERT_GT(serial.width, 0u);
      for (int threads : {2, 3}) {
        mm::ThreadPool pool(threads);
        sensor_msgs::PointCloud2 parallel;
        rc::coloredCloud(map, k, rgb, cloud_stride, {}, parallel, &pool);
        EXPECT_EQ(parallel.width, serial.width) << cloud_stride << " " << threads;
        EXPECT_EQ(parallel.row_step, serial.row_step);
        EXPECT_TRUE(parallel.data == serial.data) << cloud_stride << " " << threads;
      }
    }
  }
}

TEST(OutputConversion, ColoredCloudDeclaresItsFields) {
  const mm::DepthMap map = makeDepthMap();
  sensor_msgs::PointCloud2 cloud;
  rc::coloredCloud(map, mm::PinholeIntrinsics{100, 120, 3, 2}, cv::Mat(), 1, {}, cloud);
  ASSERT_EQ(cloud.fields.size(), 5u);
  const char* const names[] = {"x", "y", "z", "rgb", "stddev"};
  for (std::size_t f = 0; f < 5; ++f) {
    EXPECT_EQ(cloud.fields[f].name, names[f]);
    EXPECT_EQ(cloud.fields[f].offset, 4 * f);
    EXPECT_EQ(cloud.fields[f].datatype, sensor_msgs::PointField::FLOAT32);
    EXPECT_EQ(cloud.fields[f].count, 1u);
  }
  EXPECT_EQ(cloud.point_step, 20u);
  EXPECT_TRUE(cloud.is_dense);  // kept pixels only: every stddev finite
}

// Colour images on the grid: bgr8, depth through its scale where kept, sqrt(variance) through its
// scale where predicted, the no-data colour elsewhere; a recycled larger message is reshaped.
TEST(OutputConversion, DepthAndStddevColourImages) {
  const mm::DepthMap map = makeDepthMap();
  std_msgs::Header header;
  header.frame_id = "cam";
  const mm::ColorScale depth_scale(0.0, 20.0, cv::COLORMAP_TURBO, cv::Vec3b(1, 2, 3));
  const mm::ColorScale stddev_scale(0.0, 3.0, cv::COLORMAP_VIRIDIS);
  sensor_msgs::Image depth, stddev;
  stddev.data.resize(10000);  // a previous, larger output
  rc::depthColorImage(map, depth_scale, header, depth);
  rc::stddevColorImage(map, stddev_scale, header, stddev);
  for (const sensor_msgs::Image* image : {&depth, &stddev}) {
    EXPECT_EQ(image->header.frame_id, "cam");
    EXPECT_EQ(image->encoding, "bgr8");
    EXPECT_EQ(int(image->width), map.grid.cols());
    EXPECT_EQ(int(image->height), map.grid.rows());
    EXPECT_EQ(image->step, 3 * image->width);
    ASSERT_EQ(image->data.size(), 3 * map.grid.size());
  }
  for (long long i = 0; i < map.grid.size(); ++i) {
    const cv::Vec3b want_depth = map.valid[i] ? depth_scale(map.depth[i]) : cv::Vec3b(1, 2, 3);
    const cv::Vec3b want_stddev =
        i == 5 ? stddev_scale.noData() : stddev_scale(std::sqrt(map.variance[i]));
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_EQ(depth.data[3 * i + ch], want_depth[ch]) << i;
      EXPECT_EQ(stddev.data[3 * i + ch], want_stddev[ch]) << i;
    }
  }
}

TEST(ConfigMapping, DefaultsAreTheCoreDefaultsExceptRetention) {
  const mm::DepthCompletionSettings settings =
      mm::settingsFromConfig(mm::DepthCompletionConfig::__getDefault__());
  const mm::DepthCompletionParams core;
  EXPECT_EQ(settings.params.model, core.model);
  EXPECT_EQ(settings.params.radius_deg, core.radius_deg);
  EXPECT_EQ(settings.params.gp.amplitude, core.gp.amplitude);
  EXPECT_EQ(settings.params.gp.noise, core.gp.noise);
  EXPECT_EQ(settings.params.gp.length_scale_min, core.gp.length_scale_min);
  EXPECT_EQ(settings.params.gp.length_scale_max, core.gp.length_scale_max);
  EXPECT_EQ(settings.params.gp.tolerance, core.gp.tolerance);
  EXPECT_EQ(settings.params.gp.max_iterations, core.gp.max_iterations);
  EXPECT_EQ(settings.params.kernel_length_scale_deg, core.kernel_length_scale_deg);
  EXPECT_EQ(settings.params.shift.mode, core.shift.mode);
  EXPECT_EQ(settings.params.var_threshold, core.var_threshold);
  EXPECT_EQ(settings.params.max_neighbors, core.max_neighbors);
  EXPECT_EQ(settings.params.approx_tile, core.approx_tile);
  EXPECT_EQ(settings.params.guided.surface_prior, core.guided.surface_prior);
  EXPECT_EQ(settings.params.guided.lateral_prior, core.guided.lateral_prior);
  EXPECT_EQ(settings.params.guided.ground_gp_prior, core.guided.ground_gp_prior);
  EXPECT_EQ(settings.params.guided.lambda, core.guided.lambda);
  EXPECT_EQ(settings.params.guided.sky, core.guided.sky);
  EXPECT_EQ(settings.params.guided.prior_colour_sigma, core.guided.prior_colour_sigma);
  EXPECT_EQ(settings.params.ground.surface_colour_sigma, core.ground.surface_colour_sigma);
  EXPECT_EQ(settings.params.guided.prior_colour_walls, core.guided.prior_colour_walls);
  EXPECT_EQ(settings.params.ground.surface_colour_walls, core.ground.surface_colour_walls);
  EXPECT_EQ(settings.params.guided.prior_colour_fill_deg, core.guided.prior_colour_fill_deg);
  EXPECT_EQ(settings.params.guided.prior_reference_density, core.guided.prior_reference_density);
  EXPECT_EQ(settings.params.guided.prior_weight_above_returns,
            core.guided.prior_weight_above_returns);
  EXPECT_EQ(settings.params.ground.surface_colour_fill_deg, core.ground.surface_colour_fill_deg);
  EXPECT_EQ(settings.params.ground.drop_hidden_returns, core.ground.drop_hidden_returns);
  EXPECT_EQ(settings.params.ground.dense_vote_colour_sigma, core.ground.dense_vote_colour_sigma);
  EXPECT_EQ(settings.params.ground.dense_vote_colour_px, core.ground.dense_vote_colour_px);
  EXPECT_EQ(settings.params.ground.dense_edge_ratio_per_deg, core.ground.dense_edge_ratio_per_deg);
  EXPECT_EQ(settings.params.retain_percent, 80.0);  // the paper's choice, not the reference's 100
}

TEST(ConfigMapping, RoundTripsAndRejectsBadValues) {
  mm::DepthCompletionConfig config = mm::DepthCompletionConfig::__getDefault__();
  config.model = "kernel";
  config.shift = "12.5";
  config.var_threshold = 4.0;
  config.stride = 3;
  config.guided_lateral_prior = false;
  config.guided_ground_gp_prior = false;     // the default is true
  config.ground_drop_hidden_returns = true;  // the default is false
  config.guided_prior_colour_sigma = 12.5;
  config.ground_surface_colour_sigma = 7.5;
  config.guided_prior_colour_walls = false;        // the default is true
  config.ground_surface_colour_walls = false;      // the default is true
  config.guided_prior_colour_fill_deg = 4.5;       // the default is 10
  config.guided_prior_reference_density = 0.0;     // the default is 0.1
  config.guided_prior_weight_above_returns = 1.0;  // the default is 10
  config.ground_surface_colour_fill_deg = 6.5;     // the default is 0
  config.ground_dense_vote_colour_sigma = 0.0;     // the default is 40
  config.ground_dense_vote_colour_px = 24.0;       // the default is 16
  config.ground_dense_edge_ratio_per_deg = 0.0;    // the default is 0.15
  const mm::DepthCompletionSettings settings = mm::settingsFromConfig(config);
  EXPECT_EQ(settings.params.guided.prior_colour_sigma, 12.5);
  EXPECT_EQ(settings.params.ground.surface_colour_sigma, 7.5);
  EXPECT_FALSE(settings.params.guided.prior_colour_walls);
  EXPECT_FALSE(settings.params.ground.surface_colour_walls);
  EXPECT_EQ(settings.params.guided.prior_colour_fill_deg, 4.5);
  EXPECT_EQ(settings.params.guided.prior_reference_density, 0.0);
  EXPECT_EQ(settings.params.guided.prior_weight_above_returns, 1.0);
  EXPECT_EQ(settings.params.ground.surface_colour_fill_deg, 6.5);
  EXPECT_EQ(settings.params.ground.dense_vote_colour_sigma, 0.0);
  EXPECT_EQ(settings.params.ground.dense_vote_colour_px, 24.0);
  EXPECT_EQ(settings.params.ground.dense_edge_ratio_per_deg, 0.0);
  EXPECT_TRUE(settings.params.ground.drop_hidden_returns);
  EXPECT_FALSE(settings.params.guided.lateral_prior);
  EXPECT_FALSE(settings.params.guided.ground_gp_prior);
  EXPECT_EQ(settings.params.model, mm::DepthModel::kKernel);
  EXPECT_EQ(settings.params.shift.mode, mm::DepthShift::Mode::kValue);
  EXPECT_EQ(settings.params.shift.value, 12.5);
  EXPECT_EQ(settings.params.var_threshold, 4.0);
  mm::DepthCompletionConfig back = mm::DepthCompletionConfig::__getDefault__();
  mm::writeSettingsToConfig(settings, back);
  EXPECT_EQ(back.model, "kernel");
  EXPECT_EQ(back.stride, 3);
  EXPECT_FALSE(back.guided_lateral_prior);
  EXPECT_FALSE(back.guided_ground_gp_prior);
  EXPECT_TRUE(back.ground_drop_hidden_returns);
  EXPECT_EQ(back.guided_prior_colour_sigma, 12.5);
  EXPECT_EQ(back.ground_surface_colour_sigma, 7.5);
  EXPECT_FALSE(back.guided_prior_colour_walls);
  EXPECT_FALSE(back.ground_surface_colour_walls);
  EXPECT_EQ(back.guided_prior_colour_fill_deg, 4.5);
  EXPECT_EQ(back.guided_prior_reference_density, 0.0);
  EXPECT_EQ(back.guided_prior_weight_above_returns, 1.0);
  EXPECT_EQ(back.ground_surface_colour_fill_deg, 6.5);
  EXPECT_EQ(back.ground_dense_vote_colour_sigma, 0.0);
  EXPECT_EQ(back.ground_dense_vote_colour_px, 24.0);
  EXPECT_EQ(back.ground_dense_edge_ratio_per_deg, 0.0);
  EXPECT_EQ(mm::settingsFromConfig(back).params.shift.value, 12.5);

  config.model = "no_such_model";
  EXPECT_THROW(mm::settingsFromConfig(config), mm::InputError);
  config.model = "local_gp_mle";
  config.shift = "sideways";
  EXPECT_THROW(mm::settingsFromConfig(config), mm::InputError);
  config.shift = "median";
  config.length_scale_min = 20.0;  // above length_scale_max
  EXPECT_THROW(mm::settingsFromConfig(config), mm::InputError);
  config.length_scale_min = 0.1;
  config.model = "image_guided";
  config.guided_prior_reference_density = -1.0;
  EXPECT_THROW(mm::settingsFromConfig(config), mm::InputError);
  config.guided_prior_reference_density = 0.1;
  config.guided_prior_weight_above_returns = 0.0;
  EXPECT_THROW(mm::settingsFromConfig(config), mm::InputError);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

TEST(Float32Cloud, RecordsRoundTripThroughTheReader) {
  std_msgs::Header header;
  header.frame_id = "radar";
  const std::vector<float> values = {1.f, 2.f, 3.f, 0.5f, -4.f, 5.f, 6.f, 0.25f};
  const sensor_msgs::PointCloud2 cloud =
      rc::float32Cloud({"x", "y", "z", "intensity"}, values, header);
  EXPECT_EQ(cloud.header.frame_id, "radar");
  EXPECT_EQ(cloud.width, 2u);
  EXPECT_EQ(cloud.height, 1u);
  EXPECT_EQ(cloud.point_step, 16u);
  EXPECT_EQ(cloud.row_step, 32u);
  EXPECT_TRUE(cloud.is_dense);
  ASSERT_EQ(cloud.fields.size(), 4u);
  EXPECT_EQ(cloud.fields[3].name, "intensity");
  EXPECT_EQ(cloud.fields[3].offset, 12u);
  std::vector<Eigen::Vector3d> points;
  ASSERT_TRUE(rc::pointsFromCloud(cloud, Eigen::Isometry3d::Identity(), points, nullptr).ok());
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[1], Eigen::Vector3d(-4.0, 5.0, 6.0));
}

TEST(Float32Cloud, NonFiniteValueMakesItNotDense) {
  const std::vector<float> values = {1.f, std::numeric_limits<float>::quiet_NaN(), 3.f};
  const sensor_msgs::PointCloud2 cloud = rc::float32Cloud({"x", "y", "z"}, values, {});
  EXPECT_FALSE(cloud.is_dense);
  EXPECT_EQ(cloud.width, 1u);
}
