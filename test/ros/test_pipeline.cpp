// gtest-in-rostest: a short synthetic bag through launch/pipeline.launch (both nodelets in one
// manager, simulated time). The fixture writes a 4-frame synthetic street at scale 0.1 with
// make_synthetic_scene, converts it with vod_to_bag, subscribes every output, and only then plays
// the bag (`rosbag play --clock --wait-for-subscribers`, so no frame is lost to start-up order).
// Every output must arrive with sane values: finite depth > 0 exactly where the mask is 255 and NaN
// elsewhere, masks exactly {0, 255}, the cloud and the stats agreeing with the mask, conditioning
// frames of the configured render size. Nothing is written outside a temporary directory.
#include <geometry_msgs/PolygonStamped.h>
#include <gtest/gtest.h>
#include <multimodal_nvs/DepthCompletionStats.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "child_processes.hpp"
#include "rostest_helpers.hpp"

#ifndef MMNVS_TOOL_DIR
#error "MMNVS_TOOL_DIR must point at the devel space's lib/multimodal_nvs"
#endif

namespace fs = std::filesystem;
using multimodal_nvs::DepthCompletionStats;
using sensor_msgs::CameraInfo;
using sensor_msgs::Image;
using sensor_msgs::PointCloud2;

namespace {

using rostest_helpers::run;
using rostest_helpers::spawn;

constexpr int kFrames = 4;
const std::set<ros::Time> kBagStamps = {ros::Time(1.0), ros::Time(1.1), ros::Time(1.2),
                                        ros::Time(1.3)};  // vod_to_bag: start 1 s, 10 Hz

/// Every message of every output, in arrival order.
struct Outputs {
  std::mutex mutex;
  std::vector<sensor_msgs::ImageConstPtr> depth, variance, mask, conditioning, conditioning_mask;
  std::vector<sensor_msgs::CameraInfoConstPtr> depth_info, conditioning_info;
  std::vector<sensor_msgs::PointCloud2ConstPtr> points, filtered;
  std::vector<multimodal_nvs::DepthCompletionStatsConstPtr> stats;
  std::vector<geometry_msgs::PolygonStampedConstPtr> ground_plane;
  std::map<std::string, std::string> depth_diagnostics;  ///< the latest report's key/values
};

template <class Msg>
ros::Subscriber collect(ros::NodeHandle& nh, const std::string& topic, Outputs& outputs,
                        std::vector<boost::shared_ptr<const Msg>> Outputs::*slot) {
  return nh.subscribe<Msg>(topic, 20, [&outputs, slot](const boost::shared_ptr<const Msg>& msg) {
    std::lock_guard<std::mutex> lock(outputs.mutex);
    (outputs.*slot).push_back(msg);
  });
}

float floatAt(const Image& image, std::size_t row, std::size_t col) {
  float value;
  std::memcpy(&value, &image.data[row * image.step + 4 * col], sizeof value);
  return value;
}

template <class Ptr>
Ptr withStamp(const std::vector<Ptr>& messages, const ros::Time& stamp) {
  for (const Ptr& m : messages)
    if (m->header.stamp == stamp) return m;
  return Ptr();
}

class PipelineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ros::NodeHandle pnh("~");
    sensor_ = pnh.param<std::string>("sensor", "radar");
    renderer_ = pnh.param<std::string>("renderer", "/conditioning_renderer");
    // The last pcl_ros filter's output when filters sit in front of the depth nodelet.
    filtered_topic_ = pnh.param<std::string>("filtered_points", "");
    ros::NodeHandle nh;
    // The depth nodelet's retention, as its YAML set it (pipeline.launch's depth_name).
    depth_node_ = pnh.param<std::string>("depth_node", "/depth_completion");
    ASSERT_TRUE(nh.getParam(depth_node_ + "/retain_percent", retain_percent_));

    char pattern[] = "/tmp/mmnvs_pipeline_XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr) << std::strerror(errno);
    dir_ = pattern;
    const std::string tools = MMNVS_TOOL_DIR;
    ASSERT_TRUE(run(tools + "/make_synthetic_scene --output " + dir_ + "/scene --scale 0.1" +
                    " --num-frames " + std::to_string(kFrames) + " --threads 1 --quiet"));
    bag_ = dir_ + "/scene.bag";
    ASSERT_TRUE(
        run(tools + "/vod_to_bag --vod-root " + dir_ + "/scene --output " + bag_ + " --quiet"));

    outputs_ = new Outputs;
    Outputs& o = *outputs_;
    subscribers_ = new std::vector<ros::Subscriber>{
        collect(nh, "depth/image", o, &Outputs::depth),
        collect(nh, "depth/camera_info", o, &Outputs::depth_info),
        collect(nh, "depth/variance", o, &Outputs::variance),
        collect(nh, "depth/mask", o, &Outputs::mask),
        collect(nh, "depth/points", o, &Outputs::points),
        collect(nh, "depth/stats", o, &Outputs::stats),
        collect(nh, "depth/ground_plane", o, &Outputs::ground_plane),
        collect(nh, "conditioning/image", o, &Outputs::conditioning),
        collect(nh, "conditioning/camera_info", o, &Outputs::conditioning_info),
        collect(nh, "conditioning/mask", o, &Outputs::conditioning_mask)};
    if (!filtered_topic_.empty())
      subscribers_->push_back(collect(nh, filtered_topic_, o, &Outputs::filtered));
    diagnostics_sub_ = new ros::Subscriber(rostest_helpers::subscribeDiagnostics(
        nh, {"depth completion"}, o.mutex, o.depth_diagnostics));
    spinner_ = new ros::AsyncSpinner(1);
    spinner_->start();

    // Every output connected (the nodelets are loaded and have advertised) before playing.
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
    auto connected = [] {
      for (const ros::Subscriber& s : *subscribers_)
        if (s.getNumPublishers() == 0) return false;
      return true;
    };
    while (!connected() && ros::WallTime::now() < deadline)
      ros::WallDuration(0.05).sleep();
    for (const ros::Subscriber& s : *subscribers_)
      ASSERT_GT(s.getNumPublishers(), 0u) << s.getTopic() << " has no publisher after 60 s";

    // The player waits until the pipeline subscribes to every input it plays.
    player_ = spawn({"rosbag", "play", "--clock", "--quiet", "--delay=0.5", bag_,
                     "--wait-for-subscribers", "--topics", "/camera/image_raw",
                     "/camera/camera_info", "/" + sensor_ + "/points", "/tf", "/tf_static"});
    ASSERT_GT(player_, 0);
    const ros::WallTime play_deadline = ros::WallTime::now() + ros::WallDuration(60.0);
    int status = 0;
    while (ros::WallTime::now() < play_deadline) {
      if (waitpid(player_, &status, WNOHANG) == player_) {
        player_ = -1;
        break;
      }
      ros::WallDuration(0.05).sleep();
    }
    ASSERT_EQ(player_, -1) << "rosbag play did not finish within 60 s";
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "rosbag play failed";
    // Let the last frame through both nodelets: until every output has every frame, or 10 s.
    const ros::WallTime tail = ros::WallTime::now() + ros::WallDuration(10.0);
    while (ros::WallTime::now() < tail && !allFrames())
      ros::WallDuration(0.05).sleep();
    // The diagnostics (every 0.5 s of wall time) of a report after the last frame.
    const ros::WallTime report = ros::WallTime::now() + ros::WallDuration(1.5);
    while (ros::WallTime::now() < report)
      ros::WallDuration(0.05).sleep();
    ros::WallDuration(0.2).sleep();
    spinner_->stop();
  }

  static bool allFrames() {
    std::lock_guard<std::mutex> lock(outputs_->mutex);
    const Outputs& o = *outputs_;
    for (std::size_t n :
         {o.depth.size(), o.depth_info.size(), o.variance.size(), o.mask.size(), o.points.size(),
          o.stats.size(), o.ground_plane.size(), o.conditioning.size(), o.conditioning_info.size(),
          o.conditioning_mask.size()})
      if (n < std::size_t(kFrames)) return false;
    return true;
  }

  static void TearDownTestSuite() {
    if (player_ > 0) {
      kill(-player_, SIGINT);
      waitpid(player_, nullptr, 0);
    }
    delete spinner_;
    delete subscribers_;
    delete diagnostics_sub_;
    delete outputs_;
    std::error_code ignored;
    if (!dir_.empty()) fs::remove_all(dir_, ignored);
  }

  static std::string sensor_, renderer_, filtered_topic_, dir_, bag_;
  static double retain_percent_;
  static std::string depth_node_;
  static pid_t player_;
  static Outputs* outputs_;
  static std::vector<ros::Subscriber>* subscribers_;
  static ros::Subscriber* diagnostics_sub_;
  static ros::AsyncSpinner* spinner_;
};

std::string PipelineTest::sensor_, PipelineTest::renderer_, PipelineTest::filtered_topic_,
    PipelineTest::dir_, PipelineTest::bag_;
double PipelineTest::retain_percent_ = 0.0;
std::string PipelineTest::depth_node_;
pid_t PipelineTest::player_ = -1;
Outputs* PipelineTest::outputs_ = nullptr;
std::vector<ros::Subscriber>* PipelineTest::subscribers_ = nullptr;
ros::Subscriber* PipelineTest::diagnostics_sub_ = nullptr;
ros::AsyncSpinner* PipelineTest::spinner_ = nullptr;

TEST_F(PipelineTest, EveryOutputArrives) {
  const Outputs& o = *outputs_;
  const std::map<std::string, std::size_t> counts = {
      {"depth/image", o.depth.size()},
      {"depth/camera_info", o.depth_info.size()},
      {"depth/variance", o.variance.size()},
      {"depth/mask", o.mask.size()},
      {"depth/points", o.points.size()},
      {"depth/stats", o.stats.size()},
      {"depth/ground_plane", o.ground_plane.size()},
      {"conditioning/image", o.conditioning.size()},
      {"conditioning/camera_info", o.conditioning_info.size()},
      {"conditioning/mask", o.conditioning_mask.size()}};
  for (const auto& [topic, n] : counts) {
    EXPECT_GE(n, 1u) << topic << ": no message";
    EXPECT_LE(n, std::size_t(kFrames)) << topic << ": more messages than frames";
    std::printf("%-26s %zu of %d frames\n", topic.c_str(), n, kFrames);
  }
}

TEST_F(PipelineTest, DepthIsFiniteAndPositiveExactlyWhereTheMaskIsSet) {
  const Outputs& o = *outputs_;
  ASSERT_FALSE(o.depth.empty());
  for (const auto& depth : o.depth) {
    SCOPED_TRACE("depth/image at " + std::to_string(depth->header.stamp.toSec()));
    EXPECT_EQ(kBagStamps.count(depth->header.stamp), 1u);
    EXPECT_EQ(depth->header.frame_id, "camera_optical");
    ASSERT_EQ(depth->encoding, sensor_msgs::image_encodings::TYPE_32FC1);
    ASSERT_GE(depth->step, 4u * depth->width);
    ASSERT_EQ(depth->data.size(), std::size_t(depth->step) * depth->height);
    const auto info = withStamp(o.depth_info, depth->header.stamp);
    ASSERT_TRUE(info) << "no depth/camera_info with this stamp";
    EXPECT_EQ(info->width, depth->width);
    EXPECT_EQ(info->height, depth->height);
    EXPECT_GT(info->K[0], 0.0);
    const auto mask = withStamp(o.mask, depth->header.stamp);
    ASSERT_TRUE(mask) << "no depth/mask with this stamp";
    ASSERT_EQ(mask->encoding, sensor_msgs::image_encodings::MONO8);
    ASSERT_EQ(mask->width, depth->width);
    ASSERT_EQ(mask->height, depth->height);
    std::size_t kept = 0, bad_mask = 0, bad_kept = 0, bad_hole = 0;
    for (std::size_t r = 0; r < depth->height; ++r) {
      for (std::size_t c = 0; c < depth->width; ++c) {
        const uint8_t m = mask->data[r * mask->step + c];
        const float d = floatAt(*depth, r, c);
        if (m != 0 && m != 255) ++bad_mask;
        if (m == 255) {
          ++kept;
          if (!(std::isfinite(d) && d > 0.0f)) ++bad_kept;
        } else if (!std::isnan(d)) {
          ++bad_hole;
        }
      }
    }
    EXPECT_EQ(bad_mask, 0u) << "mask values other than 0 and 255";
    EXPECT_EQ(bad_kept, 0u) << "kept pixels without a finite positive depth";
    EXPECT_EQ(bad_hole, 0u) << "pixels outside the mask that are not NaN";
    EXPECT_GT(kept, 0u);
    // Retention keeps retain_percent of all grid pixels (config/radar.yaml 100: every prediction,
    // and ground_gp predicts every pixel; config/lidar.yaml 80).
    const std::size_t pixels = std::size_t(depth->width) * depth->height;
    if (retain_percent_ < 100.0) {
      EXPECT_LE(kept, std::size_t(std::ceil(retain_percent_ / 100.0 * pixels)))
          << "retention keeps more than retain_percent " << retain_percent_;
    } else {
      EXPECT_EQ(kept, pixels) << "retain_percent 100 drops pixels";
    }
  }
}

TEST_F(PipelineTest, VarianceIsNonNegativeAndFiniteWhereKept) {
  const Outputs& o = *outputs_;
  ASSERT_FALSE(o.variance.empty());
  for (const auto& variance : o.variance) {
    SCOPED_TRACE("depth/variance at " + std::to_string(variance->header.stamp.toSec()));
    ASSERT_EQ(variance->encoding, sensor_msgs::image_encodings::TYPE_32FC1);
    const auto mask = withStamp(o.mask, variance->header.stamp);
    ASSERT_TRUE(mask);
    ASSERT_EQ(mask->width, variance->width);
    ASSERT_EQ(mask->height, variance->height);
    std::size_t negative_or_nan = 0, not_finite_kept = 0;
    for (std::size_t r = 0; r < variance->height; ++r) {
      for (std::size_t c = 0; c < variance->width; ++c) {
        const float v = floatAt(*variance, r, c);
        if (!(v >= 0.0f)) ++negative_or_nan;
        if (mask->data[r * mask->step + c] == 255 && !std::isfinite(v)) ++not_finite_kept;
      }
    }
    EXPECT_EQ(negative_or_nan, 0u);
    EXPECT_EQ(not_finite_kept, 0u);
  }
}

// With pcl_ros filters in front (pipeline.test pcl:=true): the depth nodelet completed each frame
// from the filtered cloud of that stamp, point for point.
TEST_F(PipelineTest, DepthComesFromTheFilteredCloud) {
  if (filtered_topic_.empty()) GTEST_SKIP() << "no pcl_ros filters in this launch";
  const Outputs& o = *outputs_;
  ASSERT_FALSE(o.stats.empty());
  for (const auto& stats : o.stats) {
    const auto cloud = withStamp(o.filtered, stats->header.stamp);
    ASSERT_TRUE(cloud) << "no " << filtered_topic_ << " at " << stats->header.stamp;
    EXPECT_EQ(stats->points_in, std::size_t(cloud->width) * cloud->height);
  }
}

TEST_F(PipelineTest, DiagnosticsReportTheGroundPlaneOfTheLatestFrame) {
  const Outputs& o = *outputs_;
  ASSERT_FALSE(o.stats.empty());
  const auto& last = *o.stats.back();
  const auto value = [&](const std::string& key) {
    const auto it = o.depth_diagnostics.find(key);
    return it == o.depth_diagnostics.end() ? std::string("(missing)") : it->second;
  };
  EXPECT_EQ(value("ground plane source"), last.ground_source);
  char height[32], pitch[32];
  std::snprintf(height, sizeof height, "%.2f", last.ground_camera_height);
  std::snprintf(pitch, sizeof pitch, "%.2f", last.ground_pitch_deg);
  EXPECT_EQ(value("ground plane camera height (m)"), height);
  EXPECT_EQ(value("ground plane pitch (deg)"), pitch);
  EXPECT_NE(value("ground plane roll (deg)"), "(missing)");
  // radar.yaml's image_guided also says how dense the returns were and the prior weight that
  // followed; lidar.yaml's ground_gp has neither.
  if (sensor_ == "radar") {
    char density[32], weight[32];
    std::snprintf(density, sizeof density, "%.3f", last.guided_return_density);
    std::snprintf(weight, sizeof weight, "%.2e", last.guided_prior_weight);
    EXPECT_EQ(value("returns per square degree"), density);
    EXPECT_EQ(value("image_guided prior weight"), weight);
    char band_top[32];
    std::snprintf(band_top, sizeof band_top, "%.2f", last.guided_band_top_deg);
    EXPECT_EQ(value("returns' band top (deg)"), band_top);
  } else {
    EXPECT_EQ(value("image_guided prior weight"), "(missing)");
  }
}

TEST_F(PipelineTest, TheGroundPlanePolygonIsTheSyntheticRoad) {
  const Outputs& o = *outputs_;
  ASSERT_EQ(o.ground_plane.size(), o.stats.size());  // both configs' models have a ground plane
  for (const auto& polygon : o.ground_plane) {
    SCOPED_TRACE("depth/ground_plane at " + std::to_string(polygon->header.stamp.toSec()));
    ASSERT_TRUE(withStamp(o.stats, polygon->header.stamp));
    EXPECT_EQ(polygon->header.frame_id, o.depth.front()->header.frame_id);
    ASSERT_EQ(polygon->polygon.points.size(), 4u);
    for (const auto& corner : polygon->polygon.points) {
      // The level synthetic camera 1.3 m above the road: y (down) is the height everywhere (the
      // fitted plane's tilt, within 1 deg, moves the far corners by at most 0.7 m).
      EXPECT_NEAR(corner.y, 1.3, 0.1 + 0.0175 * corner.z);
      EXPECT_GE(corner.z, 1.5);
    }
  }
}

TEST_F(PipelineTest, StatsAndCloudAgreeWithTheMask) {
  const Outputs& o = *outputs_;
  ASSERT_FALSE(o.stats.empty());
  // The node's dynamic_reconfigure server put its whole configuration on the parameter server.
  double prior_weight = 0.0, reference_density = 0.0;
  if (sensor_ == "radar") {
    ros::NodeHandle nh;
    ASSERT_TRUE(nh.getParam(depth_node_ + "/guided_prior_weight", prior_weight));
    ASSERT_TRUE(nh.getParam(depth_node_ + "/guided_prior_reference_density", reference_density));
  }
  for (const auto& stats : o.stats) {
    SCOPED_TRACE("depth/stats at " + std::to_string(stats->header.stamp.toSec()));
    EXPECT_GT(stats->points_in, 0u);
    EXPECT_GT(stats->points_in_view, 0u);
    EXPECT_LE(stats->points_in_view, stats->points_in);
    EXPECT_GE(stats->compute_ms, 0.0);
    const auto mask = withStamp(o.mask, stats->header.stamp);
    ASSERT_TRUE(mask);
    std::size_t kept = 0;
    for (uint8_t m : mask->data)
      kept += m == 255;
    EXPECT_EQ(stats->kept_pixels, kept);
    // Both configs run a model with a ground plane (radar.yaml image_guided on ground_gp,
    // lidar.yaml ground_gp): the stats say which mode ran; only the dense mode filters returns.
    EXPECT_TRUE(stats->ground_mode == "dense" || stats->ground_mode == "sparse" ||
                stats->ground_mode == "sparse_tiled")
        << stats->ground_mode;
    EXPECT_FALSE(stats->ground_source.empty());
    // The synthetic camera is level, 1.3 m above the road: the plane from the parameters
    // (demo_synthetic.yaml, radar) or fitted to the returns (LiDAR) is that one.
    EXPECT_NEAR(stats->ground_camera_height, 1.3, 0.1) << stats->ground_source;
    EXPECT_NEAR(stats->ground_pitch_deg, 0.0, 1.0) << stats->ground_source;
    EXPECT_NEAR(stats->ground_roll_deg, 0.0, 1.0) << stats->ground_source;
    if (stats->ground_mode != "dense") {
      EXPECT_EQ(stats->ground_hidden_returns, -1);
      EXPECT_EQ(stats->ground_edge_ratio, -1.0f);
    } else {
      EXPECT_GE(stats->ground_edge_ratio, 0.1f);  // lidar.yaml's ratio, or more on sparse rings
    }
    EXPECT_LE(stats->ground_hidden_returns, int(stats->points_in));
    EXPECT_FALSE(stats->ground_single_scan_plane);  // 3D radar and a scanning LiDAR
    if (sensor_ == "radar") {
      // image_guided on ground_gp's prior: the node's prior weight scaled by the returns' density
      // against its reference density, the factor within 0.25-10.
      EXPECT_GT(stats->guided_return_density, 0.0f);
      const double factor =
          std::clamp(stats->guided_return_density / reference_density, 0.25, 10.0);
      EXPECT_NEAR(stats->guided_prior_weight, prior_weight * factor, 1e-5 * prior_weight);
      // The synthetic 3D radar's returns end below the top of the image: a band, within the
      // camera's vertical view.
      EXPECT_TRUE(std::isfinite(stats->guided_band_top_deg));
      EXPECT_LT(std::abs(stats->guided_band_top_deg), 30.0f);
    } else {
      EXPECT_EQ(stats->guided_return_density, -1.0f);
      EXPECT_EQ(stats->guided_prior_weight, -1.0f);
      EXPECT_TRUE(std::isnan(stats->guided_band_top_deg));
    }
  }
  ASSERT_FALSE(o.points.empty());
  for (const auto& cloud : o.points) {
    SCOPED_TRACE("depth/points at " + std::to_string(cloud->header.stamp.toSec()));
    EXPECT_EQ(cloud->header.frame_id, "camera_optical");
    std::map<std::string, const sensor_msgs::PointField*> fields;
    for (const auto& f : cloud->fields)
      fields[f.name] = &f;
    for (const char* name : {"x", "y", "z"}) {
      ASSERT_TRUE(fields.count(name)) << "no field " << name;
      ASSERT_EQ(fields[name]->datatype, sensor_msgs::PointField::FLOAT32);
    }
    EXPECT_TRUE(fields.count("rgb"));
    const std::size_t n = std::size_t(cloud->width) * cloud->height;
    ASSERT_GT(n, 0u);
    ASSERT_GE(cloud->data.size(), n * cloud->point_step);
    const auto mask = withStamp(o.mask, cloud->header.stamp);
    if (mask) {
      std::size_t kept = 0;
      for (uint8_t m : mask->data)
        kept += m == 255;
      EXPECT_LE(n, kept) << "more cloud points than kept pixels";
    }
    const uint32_t offsets[3] = {fields["x"]->offset, fields["y"]->offset, fields["z"]->offset};
    std::size_t bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
      float xyz[3];
      for (int k = 0; k < 3; ++k)
        std::memcpy(&xyz[k], &cloud->data[i * cloud->point_step + offsets[k]], sizeof(float));
      if (!(std::isfinite(xyz[0]) && std::isfinite(xyz[1]) && xyz[2] > 0.0f)) ++bad;
    }
    EXPECT_EQ(bad, 0u) << "cloud points not finite or not in front of the camera";
  }
}

TEST_F(PipelineTest, ConditioningFramesHaveTheRenderSize) {
  ros::NodeHandle nh;
  int height = 0, width = 0;
  ASSERT_TRUE(nh.getParam(renderer_ + "/render_height", height));
  ASSERT_TRUE(nh.getParam(renderer_ + "/render_width", width));
  const Outputs& o = *outputs_;
  ASSERT_FALSE(o.conditioning.empty());
  for (const auto& image : o.conditioning) {
    SCOPED_TRACE("conditioning/image at " + std::to_string(image->header.stamp.toSec()));
    EXPECT_EQ(kBagStamps.count(image->header.stamp), 1u);
    EXPECT_EQ(int(image->height), height);
    EXPECT_EQ(int(image->width), width);
    ASSERT_EQ(image->encoding, sensor_msgs::image_encodings::RGB8);
    ASSERT_EQ(image->data.size(), std::size_t(image->step) * image->height);
    std::size_t lit = 0;
    for (uint8_t v : image->data)
      lit += v != 0;
    EXPECT_GT(lit, 0u) << "all black";
    const auto info = withStamp(o.conditioning_info, image->header.stamp);
    ASSERT_TRUE(info);
    EXPECT_EQ(int(info->height), height);
    EXPECT_EQ(int(info->width), width);
  }
  ASSERT_FALSE(o.conditioning_mask.empty());
  for (const auto& mask : o.conditioning_mask) {
    SCOPED_TRACE("conditioning/mask at " + std::to_string(mask->header.stamp.toSec()));
    ASSERT_EQ(mask->encoding, sensor_msgs::image_encodings::MONO8);
    EXPECT_EQ(int(mask->height), height);
    EXPECT_EQ(int(mask->width), width);
    std::size_t other = 0, set = 0;
    for (std::size_t r = 0; r < mask->height; ++r) {
      for (std::size_t c = 0; c < mask->width; ++c) {
        const uint8_t m = mask->data[r * mask->step + c];
        set += m == 255;
        other += m != 0 && m != 255;
      }
    }
    EXPECT_EQ(other, 0u) << "mask values other than 0 and 255";
    EXPECT_GT(set, 0u) << "nothing rendered";
  }
}

// The first frame is the keyframe rendered into its own pose: it must cover about what the depth
// mask keeps (80 % of the pixels), up to the splat's edge handling.
TEST_F(PipelineTest, KeyframeRenderCoversTheKeptDepth) {
  const Outputs& o = *outputs_;
  const auto mask = withStamp(o.conditioning_mask, *kBagStamps.begin());
  ASSERT_TRUE(mask) << "no conditioning/mask for the first (key) frame";
  std::size_t set = 0;
  for (std::size_t r = 0; r < mask->height; ++r)
    for (std::size_t c = 0; c < mask->width; ++c)
      set += mask->data[r * mask->step + c] == 255;
  const double coverage = double(set) / (double(mask->width) * mask->height);
  EXPECT_GT(coverage, 0.5) << "the keyframe seen from its own pose covers only " << coverage;
}

TEST_F(PipelineTest, ConditioningFramesCarryTheCameraHeader) {
  const Outputs& o = *outputs_;
  for (const auto& image : o.conditioning) {
    SCOPED_TRACE("conditioning/image at " + std::to_string(image->header.stamp.toSec()));
    EXPECT_EQ(image->header.frame_id, "camera_optical");
    // The renderer follows the camera: every camera image of the bag gets a frame, whether or not
    // a depth set came with it.
    EXPECT_EQ(kBagStamps.count(image->header.stamp), 1u) << "not a camera stamp of the bag";
  }
  for (const auto& mask : o.conditioning_mask) {
    SCOPED_TRACE("conditioning/mask at " + std::to_string(mask->header.stamp.toSec()));
    EXPECT_EQ(mask->header.frame_id, "camera_optical");
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_pipeline");
  ros::NodeHandle nh;  // keeps the node alive for the whole run
  return RUN_ALL_TESTS();
}
