// The synthetic street: deterministic for a seed, a complete View-of-Delft layout, exact depth
// ground truth, and radar/LiDAR returns that lie on the surfaces the camera sees within the
// simulated noise.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include "tool_runner.hpp"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "multimodal_nvs/core/synthetic/dataset.hpp"

namespace io = multimodal_nvs::io;
namespace syn = multimodal_nvs::synthetic;
namespace fs = std::filesystem;

namespace {

/// A small scene that is quick to make: 194 x 122 pixels, LiDAR at 1 deg steps.
syn::SyntheticDatasetParams smallParams(std::uint64_t seed, int frames = 2) {
  syn::SyntheticDatasetParams p;
  p.seed = seed;
  p.frames = frames;
  p.scale = 0.1;
  p.lidar.azimuth_step_deg = 1.0;
  return p;
}

syn::SyntheticDatasetParams noiseFree(syn::SyntheticDatasetParams p) {
  p.radar.range_sigma = p.radar.azimuth_sigma_deg = p.radar.elevation_sigma_deg = 0.0;
  p.radar.clutter_fraction = 0.0;
  p.lidar.range_sigma = 0.0;
  return p;
}

std::string freshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "synthetic_" + name;
  fs::remove_all(dir);
  return dir;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Every regular file under `root` with its bytes, keyed by relative path.
std::map<std::string, std::string> treeContents(const std::string& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), root).string()] = readBytes(e.path());
  }
  return files;
}

/// Depth ground truth of one frame.
struct DepthImage {
  int height = 0, width = 0;
  std::vector<float> z;
  float at(int v, int u) const { return z[static_cast<std::size_t>(v) * width + u]; }
};

DepthImage readDepth(const std::string& path) {
  const io::NpyArray a = io::readNpy(path);
  EXPECT_EQ(a.dtype, "<f4") << path;
  EXPECT_EQ(a.shape.size(), 2u) << path;
  DepthImage d;
  d.height = static_cast<int>(a.shape[0]);
  d.width = static_cast<int>(a.shape[1]);
  d.z = a.asFloat();
  return d;
}

/// Where a sensor point lands relative to the ground-truth surface seen by the camera.
struct SurfaceResidual {
  bool in_image = false;
  bool planar = false;    ///< the 4 x 4 pixels around it lie on one plane (no depth edge)
  double residual = 0.0;  ///< point z minus ground-truth z at its exact projection (m)
  double z = 0.0;
};

/// Inverse depth is affine in (u, v) on a plane, so a plane fitted to the 4 x 4 pixel centres
/// around the projection gives the exact ground-truth depth there; patches that are not planar
/// (object edges, creases) are flagged and skipped.
SurfaceResidual surfaceResidual(const Eigen::Vector3d& p_sensor, const io::KittiCalib& calib,
                                const DepthImage& depth) {
  SurfaceResidual r;
  const multimodal_nvs::SensorToCamera t = calib.sensorToCamera();
  const auto k = calib.intrinsics();
  const Eigen::Vector3d p = t.leftCols<3>() * p_sensor + t.col(3);
  if (p.z() <= 0.1) return r;
  const double u = k.fx * p.x() / p.z() + k.cx, v = k.fy * p.y() / p.z() + k.cy;
  if (u < 1 || v < 1 || u >= depth.width - 2 || v >= depth.height - 2) return r;
  r.in_image = true;
  r.z = p.z();
  const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
  // Least-squares plane 1/z = c0 du + c1 dv + c2 through the 16 pixel centres (normal equations).
  double inv_z[16];
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  int n = 0;
  for (int dv = -1; dv <= 2; ++dv) {
    for (int du = -1; du <= 2; ++du) {
      const float z = depth.at(v0 + dv, u0 + du);
      if (!(z > 0.0f)) return r;  // sky in the patch
      inv_z[n++] = 1.0 / z;
      const Eigen::Vector3d row(du, dv, 1.0);
      normal += row * row.transpose();
      rhs += row * inv_z[n - 1];
    }
  }
  const Eigen::Vector3d plane = normal.ldlt().solve(rhs);
  double worst = 0.0, mean = 0.0;
  n = 0;
  for (int dv = -1; dv <= 2; ++dv) {
    for (int du = -1; du <= 2; ++du, ++n) {
      worst = std::max(worst, std::abs(plane.dot(Eigen::Vector3d(du, dv, 1.0)) - inv_z[n]));
      mean += inv_z[n] / 16.0;
    }
  }
  if (worst > 1e-5 * mean) return r;
  r.planar = true;
  r.residual = p.z() - 1.0 / plane.dot(Eigen::Vector3d(u - u0, v - v0, 1.0));
  return r;
}

using multimodal_nvs::test::ToolResult;

ToolResult runTool(const std::string& args) {
  return multimodal_nvs::test::runTool("make_synthetic_scene", args);
}

}  // namespace

TEST(SyntheticScene, SameSeedGivesIdenticalBytesWhateverTheThreadCount) {
  const std::string a = freshDir("seed7_a"), b = freshDir("seed7_b"), c = freshDir("seed8");
  syn::SyntheticDatasetParams p = smallParams(7);
  p.threads = 1;
  syn::SyntheticDataset(p).write(a);
  p.threads = 3;
  syn::SyntheticDataset(p).write(b);
  const auto files_a = treeContents(a), files_b = treeContents(b);
  ASSERT_EQ(files_a.size(), files_b.size());
  for (const auto& [path, bytes] : files_a) {
    ASSERT_TRUE(files_b.count(path)) << path;
    EXPECT_TRUE(bytes == files_b.at(path)) << path << " differs between two runs with seed 7";
  }

  syn::SyntheticDataset(smallParams(8)).write(c);
  const auto files_c = treeContents(c);
  for (const char* path : {"lidar/training/image_2/00000.jpg", "radar/training/velodyne/00000.bin",
                           "lidar/training/velodyne/00001.bin", "depth_gt/00000.npy"}) {
    EXPECT_FALSE(files_a.at(path) == files_c.at(path)) << path << " is the same for seeds 7 and 8";
  }
}

TEST(SyntheticScene, WritesTheCompleteViewOfDelftLayout) {
  const std::string root = freshDir("layout");
  syn::SyntheticDatasetParams p = smallParams(3, 3);
  p.first_frame = 8350;
  const syn::SyntheticDataset dataset(p);
  dataset.write(root);
  const auto& cam = dataset.camera();
  EXPECT_EQ(cam.size.width, 194);
  EXPECT_EQ(cam.size.height, 122);
  EXPECT_TRUE(io::fileExists(root + "/scene.json"));

  for (int i = 0; i < 3; ++i) {
    const io::VodFrame f{root, 8350 + i};
    SCOPED_TRACE(f.id());
    for (const std::string& path :
         {f.image(), f.pose(), f.points("radar"), f.points("lidar"), f.calib("radar"),
          f.calib("lidar"), root + "/depth_gt/" + f.id() + ".npy"}) {
      EXPECT_TRUE(io::fileExists(path)) << path;
    }
    const cv::Mat image = cv::imread(f.image(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty());
    EXPECT_EQ(image.cols, cam.size.width);
    EXPECT_EQ(image.rows, cam.size.height);
    const DepthImage depth = readDepth(root + "/depth_gt/" + f.id() + ".npy");
    EXPECT_EQ(depth.width, cam.size.width);
    EXPECT_EQ(depth.height, cam.size.height);

    // Calibrations: P2 is the camera, Tr_velo_to_cam the rig's extrinsic.
    for (const char* sensor : {"radar", "lidar"}) {
      const io::KittiCalib calib = io::readKittiCalib(f.calib(sensor));
      EXPECT_NEAR(calib.intrinsics().fx, cam.intrinsics.fx, 1e-9);
      EXPECT_NEAR(calib.intrinsics().cy, cam.intrinsics.cy, 1e-9);
      const auto expected = std::string(sensor) == "radar" ? dataset.rig().radarToCamera()
                                                           : dataset.rig().lidarToCamera();
      EXPECT_LT((calib.sensorToCamera() - expected).cwiseAbs().maxCoeff(), 1e-9) << sensor;
    }

    // Poses: the three VoD keys, consistent with each other.
    const Eigen::Matrix4d odom = io::readVodPose(f.pose(), "odomToCamera");
    const Eigen::Matrix4d map = io::readVodPose(f.pose(), "mapToCamera");
    const Eigen::Matrix4d utm = io::readVodPose(f.pose(), "UTMToCamera");
    EXPECT_LT((odom - dataset.cameraToOdom(i).matrix()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((map - (syn::SyntheticDataset::mapFromOdom() * dataset.cameraToOdom(i)).matrix())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-9);
    EXPECT_GT(utm(1, 3), 5e6);           // UTM northing of Delft
    EXPECT_NEAR(odom(2, 3), 1.3, 1e-9);  // camera height above the road

    // Radar: a few hundred 7-float returns; LiDAR: 4-float returns.
    const auto radar = io::readFloatRecords(f.points("radar"), 7);
    EXPECT_GE(radar.size() / 7, 100u);
    EXPECT_LE(radar.size() / 7, 1000u);
    const auto lidar = io::readFloatRecords(f.points("lidar"), 4);
    EXPECT_GE(lidar.size() / 4, 5000u);
  }
}

TEST(SyntheticScene, DepthGroundTruthIsExactOnTheRoad) {
  syn::SyntheticDatasetParams p = smallParams(5, 1);
  p.path.sway = 0.0;  // camera axes aligned with the street: no roll, no pitch either way
  const syn::SyntheticDataset dataset(p);
  const syn::SyntheticFrame f = dataset.frame(0);
  const auto& k = dataset.camera().intrinsics;
  const int h = dataset.camera().size.height;
  // The bottom rows in the middle see the road 1.3 m below the camera: z = 1.3 fy / (v - cy).
  for (int v = h - 10; v < h; ++v) {
    const int u = static_cast<int>(k.cx);
    EXPECT_NEAR(f.camera.depth.at<float>(v, u), 1.3 * k.fy / (v - k.cy), 1e-5) << "row " << v;
  }
  // The sky (top centre, looking along the street above the buildings) has no depth.
  EXPECT_EQ(f.camera.depth.at<float>(0, static_cast<int>(k.cx)), 0.0f);
  // Depth is finite and positive elsewhere.
  int valid = 0;
  for (int i = 0; i < f.camera.depth.rows * f.camera.depth.cols; ++i) {
    const float z = f.camera.depth.ptr<float>()[i];
    ASSERT_TRUE(std::isfinite(z) && z >= 0.0f);
    valid += z > 0.0f;
  }
  EXPECT_GT(valid, f.camera.depth.rows * f.camera.depth.cols / 2);
}

TEST(SyntheticScene, NoiseFreeReturnsLieExactlyOnTheSurfacesTheCameraSees) {
  const std::string root = freshDir("noise_free");
  syn::SyntheticDataset(noiseFree(smallParams(11))).write(root);
  for (int i = 0; i < 2; ++i) {
    const io::VodFrame f{root, i};
    const DepthImage depth = readDepth(root + "/depth_gt/" + f.id() + ".npy");
    for (const char* sensor : {"radar", "lidar"}) {
      SCOPED_TRACE(std::string(sensor) + " frame " + f.id());
      const int n = std::string(sensor) == "radar" ? 7 : 4;
      const auto values = io::readFloatRecords(f.points(sensor), n);
      const io::KittiCalib calib = io::readKittiCalib(f.calib(sensor));
      int in_image = 0, planar = 0, on_surface = 0, in_front = 0;
      for (std::size_t j = 0; j < values.size(); j += n) {
        const Eigen::Vector3d p(values[j], values[j + 1], values[j + 2]);
        const SurfaceResidual r = surfaceResidual(p, calib, depth);
        in_image += r.in_image;
        if (!r.planar) continue;
        ++planar;
        on_surface += std::abs(r.residual) < 1e-4 * r.z;
        // A point in front of the visible surface would have been seen by the camera.
        in_front += r.residual < -1e-4 * r.z;
      }
      EXPECT_GT(in_image, std::string(sensor) == "radar" ? 50 : 1000);
      EXPECT_GT(planar, in_image / 2);
      // Only objects thinner than a pixel (a 7 cm sign post 20 m away at this scale) can slip
      // between the pixel centres of the ground truth.
      EXPECT_LE(in_front, planar / 500 + 1);
      // The rest are surfaces the sensor sees and the camera does not (parallax occlusion).
      EXPECT_GT(on_surface, 0.85 * planar) << on_surface << " of " << planar;
    }
  }
}

// A radar sees past the first surface (under vehicles, through foliage, multipath): with
// pass_through 1 every detection comes from the surface behind the first one the radar meets, so
// most noise-free returns lie behind the visible surface instead of on it.
TEST(SyntheticScene, RadarPassThroughPutsReturnsBehindTheVisibleSurface) {
  for (const double pass_through : {0.0, 1.0}) {
    SCOPED_TRACE("pass_through " + std::to_string(pass_through));
    syn::SyntheticDatasetParams p = noiseFree(smallParams(11, 1));
    p.radar.pass_through = pass_through;
    const std::string root = freshDir("pass_through");
    syn::SyntheticDataset(p).write(root);
    const io::VodFrame f{root, 0};
    const DepthImage depth = readDepth(root + "/depth_gt/" + f.id() + ".npy");
    const auto values = io::readFloatRecords(f.points("radar"), 7);
    const io::KittiCalib calib = io::readKittiCalib(f.calib("radar"));
    int planar = 0, on_surface = 0, behind = 0;
    for (std::size_t j = 0; j < values.size(); j += 7) {
      const SurfaceResidual r =
          surfaceResidual(Eigen::Vector3d(values[j], values[j + 1], values[j + 2]), calib, depth);
      if (!r.planar) continue;
      ++planar;
      on_surface += std::abs(r.residual) < 1e-4 * r.z;
      behind += r.residual > 0.2 * (r.z - r.residual);  // 20 % behind the visible depth
    }
    ASSERT_GT(planar, 20);
    if (pass_through == 0.0) {
      EXPECT_GT(on_surface, 0.85 * planar);
      EXPECT_LT(behind, 0.1 * planar);
    } else {
      // Not all leave the visible surface: where the radar's first surface is hidden from the
      // camera (parallax) the surface behind it can be the visible one.
      EXPECT_LT(on_surface, 0.3 * planar) << on_surface << " of " << planar;
      EXPECT_GT(behind, 0.3 * planar) << behind << " of " << planar;
    }
  }
}

// Multipath ghosts: the detection lies along the beam at 1.1 to ghost_range_factor_max times the
// range of the surface the beam met, so behind the surface the camera sees there; without ghosts
// (and noise) every surface return is at the surface's range.
TEST(SyntheticScene, RadarGhostsLieAlongTheBeamBehindTheSurface) {
  for (const double ghosts : {0.0, 0.5}) {
    SCOPED_TRACE("ghosts " + std::to_string(ghosts));
    syn::SyntheticDatasetParams p = noiseFree(smallParams(13, 1));
    p.radar.clutter_fraction = 0.0;
    p.radar.ghosts = ghosts;
    p.radar.ghost_range_factor_max = 1.6;
    const syn::SyntheticFrame frame = syn::SyntheticDataset(p).frame(0);
    int ghost_count = 0;
    for (const syn::RadarReturn& ret : frame.radar) {
      const double ratio = ret.position.cast<double>().norm() / ret.true_range;
      if (ret.ghost) {
        ++ghost_count;
        EXPECT_GE(ratio, syn::kMinGhostRangeFactor - 1e-5);
        EXPECT_LE(ratio, 1.6 + 1e-5);
      } else {
        EXPECT_NEAR(ratio, 1.0, 1e-5);
      }
    }
    ASSERT_GT(frame.radar.size(), 40u);
    const double share = double(ghost_count) / frame.radar.size();
    if (ghosts == 0.0) {
      EXPECT_EQ(ghost_count, 0);
    } else {
      EXPECT_GT(share, 0.35);
      EXPECT_LT(share, 0.65);
    }
  }
}

// A 2D radar measures range and azimuth, not elevation: each detection of the 3D radar of the same
// seed comes back at the same range and azimuth on the radar's own plane (z = 0), clutter
// included, and nothing else of the scan changes.
TEST(SyntheticScene, A2dRadarReportsTheSameDetectionsOnItsOwnPlane) {
  syn::SyntheticDatasetParams p = smallParams(17, 1);
  const syn::SyntheticFrame three_d = syn::SyntheticDataset(p).frame(0);
  p.radar.measures_elevation = false;
  const syn::SyntheticFrame two_d = syn::SyntheticDataset(p).frame(0);
  ASSERT_EQ(three_d.radar.size(), two_d.radar.size());
  ASSERT_GT(two_d.radar.size(), 40u);
  int off_plane = 0;
  for (std::size_t i = 0; i < two_d.radar.size(); ++i) {
    const Eigen::Vector3f a = three_d.radar[i].position, b = two_d.radar[i].position;
    EXPECT_EQ(b.z(), 0.0f) << i;
    EXPECT_NEAR(b.norm(), a.norm(), 1e-4f * a.norm()) << i;
    EXPECT_NEAR(std::atan2(b.y(), b.x()), std::atan2(a.y(), a.x()), 1e-5f) << i;
    EXPECT_EQ(two_d.radar[i].clutter, three_d.radar[i].clutter) << i;
    EXPECT_EQ(two_d.radar[i].rcs, three_d.radar[i].rcs) << i;
    off_plane += std::abs(a.z()) > 0.1f;
  }
  EXPECT_GT(off_plane, 10);  // the 3D radar's were not on that plane
  EXPECT_EQ(two_d.lidar.size(), three_d.lidar.size());
}

TEST(SyntheticScene, NoisyReturnsLieOnTheSurfacesWithinTheSimulatedNoise) {
  const std::string root = freshDir("noisy");
  const syn::SyntheticDatasetParams p = smallParams(12);
  const syn::SyntheticDataset dataset(p);
  dataset.write(root);
  const double deg = M_PI / 180.0;
  for (int i = 0; i < 2; ++i) {
    const io::VodFrame f{root, i};
    const DepthImage depth = readDepth(root + "/depth_gt/" + f.id() + ".npy");
    const syn::SyntheticFrame frame = dataset.frame(i);  // same returns, with the clutter flags

    const auto radar = io::readFloatRecords(f.points("radar"), 7);
    ASSERT_EQ(radar.size(), 7 * frame.radar.size());
    const io::KittiCalib radar_calib = io::readKittiCalib(f.calib("radar"));
    int planar = 0, within = 0, in_front = 0, clutter = 0;
    double sum_sq = 0.0;
    for (std::size_t j = 0; j < frame.radar.size(); ++j) {
      const syn::RadarReturn& ret = frame.radar[j];
      ASSERT_EQ(radar[7 * j], ret.position.x());
      ASSERT_EQ(radar[7 * j + 3], ret.rcs);
      if (ret.clutter) {
        ++clutter;
        continue;
      }
      // A static world: ego-motion compensation leaves only the velocity noise.
      EXPECT_LT(std::abs(ret.v_r_compensated), 5 * p.radar.velocity_sigma);
      const SurfaceResidual r = surfaceResidual(ret.position.cast<double>(), radar_calib, depth);
      if (!r.planar) continue;
      ++planar;
      // Range noise plus the sideways shift of the angle noise, seen at up to ~60 deg incidence.
      const double range = ret.position.norm();
      const double tolerance =
          3.0 * p.radar.range_sigma +
          3.0 * range * std::max(p.radar.azimuth_sigma_deg, p.radar.elevation_sigma_deg) * deg *
              2.0;
      within += std::abs(r.residual) < tolerance;
      in_front += r.residual < -tolerance;
      sum_sq += r.residual * r.residual;
    }
    SCOPED_TRACE("radar frame " + f.id());
    EXPECT_GT(planar, 50);
    EXPECT_GT(within, 0.85 * planar) << within << " of " << planar;
    EXPECT_LT(in_front, 0.03 * planar + 1) << in_front << " of " << planar;
    EXPECT_GT(std::sqrt(sum_sq / planar), 0.3 * p.radar.range_sigma) << "no noise was simulated";
    const double clutter_share = double(clutter) / frame.radar.size();
    EXPECT_NEAR(clutter_share, p.radar.clutter_fraction, 0.03);

    const auto lidar = io::readFloatRecords(f.points("lidar"), 4);
    const io::KittiCalib lidar_calib = io::readKittiCalib(f.calib("lidar"));
    int lidar_planar = 0, lidar_within = 0, lidar_front = 0;
    std::set<long> rings;
    for (std::size_t j = 0; j < lidar.size(); j += 4) {
      const Eigen::Vector3d q(lidar[j], lidar[j + 1], lidar[j + 2]);
      EXPECT_TRUE(lidar[j + 3] >= 0.0f && lidar[j + 3] <= 255.0f);
      // Range noise moves a return along its beam, so the elevation still names its ring.
      rings.insert(std::lround(std::atan2(q.z(), q.head<2>().norm()) / deg * 100.0));
      const SurfaceResidual r = surfaceResidual(q, lidar_calib, depth);
      if (!r.planar) continue;
      ++lidar_planar;
      lidar_within += std::abs(r.residual) < 4.0 * p.lidar.range_sigma;
      lidar_front += r.residual < -4.0 * p.lidar.range_sigma;
    }
    EXPECT_EQ(rings.size(), 64u) << "LiDAR rings";
    EXPECT_GT(lidar_within, 0.88 * lidar_planar) << lidar_within << " of " << lidar_planar;
    EXPECT_LT(lidar_front, 0.01 * lidar_planar + 1);
  }
}

TEST(SyntheticScene, RadarSeesTheStaticWorldApproachWhileDrivingForward) {
  const syn::SyntheticDataset dataset(smallParams(4, 1));
  const syn::SyntheticFrame f = dataset.frame(0);
  int ahead = 0, approaching = 0;
  for (const auto& r : f.radar) {
    if (r.clutter || r.position.x() < 5.0f || std::abs(r.position.y()) > 0.3f * r.position.x()) {
      continue;
    }
    ++ahead;
    // Radial velocity of a static point almost straight ahead ~ -speed.
    approaching += r.v_r < -0.8 * dataset.params().path.speed;
  }
  EXPECT_GT(ahead, 5);
  EXPECT_GT(approaching, 0.9 * ahead);
}

TEST(SyntheticScene, ToolWritesTheLayoutAndRejectsBadOptions) {
  const std::string root = freshDir("tool");
  const auto ok = runTool("--output " + root +
                          " --scale 0.05 --num-frames 2 --first-frame 7 --quiet "
                          "--lidar-azimuth-step 2");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("\"frames\": 2"), std::string::npos) << ok.output;
  EXPECT_TRUE(io::fileExists(io::VodFrame{root, 8}.image()));
  EXPECT_TRUE(io::fileExists(root + "/depth_gt/00008.npy"));

  const struct {
    std::string args, expected;
    int code;
  } cases[] = {
      {"--scale 0.1", "--output", 2},
      {"--output " + root + " --scale 0", "--scale", 2},
      {"--output " + root + " --num-frames 0", "--num-frames", 2},
      {"--output " + root + " --seed -3", "--seed", 2},
      {"--output /proc/forbidden --scale 0.05 --num-frames 1", "/proc/forbidden", 1},
  };
  for (const auto& c : cases) {
    const auto r = runTool(c.args);
    EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
}

TEST(SyntheticScene, CameraHeightAndPitchSetWhereTheRoadIs) {
  syn::SyntheticDatasetParams p = smallParams(5, 1);
  p.path.sway = 0.0;  // no yaw: the road's depth below the centre column is analytic
  for (const double height : {1.2, 2.2}) {
    for (const double pitch_deg : {-4.0, 8.0}) {
      SCOPED_TRACE("height " + std::to_string(height) + " pitch " + std::to_string(pitch_deg));
      p.camera_height = height;
      p.camera_pitch_deg = pitch_deg;
      const syn::SyntheticDataset dataset(p);
      EXPECT_NEAR(dataset.cameraToOdom(0).translation().z(), height, 1e-12);
      const syn::SyntheticFrame f = dataset.frame(0);
      const auto& k = dataset.camera().intrinsics;
      const int h = dataset.camera().size.height;
      const double pitch = pitch_deg * M_PI / 180.0;
      // The ray through (cx, v) falls (v - cy) / fy cos(pitch) - sin(pitch) per metre of camera
      // z; it meets the road at z = height / that.
      for (int v = h - 8; v < h; ++v) {
        const double fall = (v - k.cy) / k.fy * std::cos(pitch) - std::sin(pitch);
        ASSERT_GT(fall, 0.0);
        EXPECT_NEAR(f.camera.depth.at<float>(v, static_cast<int>(k.cx)), height / fall,
                    1e-4 * height / fall)
            << "row " << v;
      }
      // The LiDAR stays level on the roof, 0.6 m above the camera.
      const Eigen::Matrix<double, 3, 4> lidar = dataset.rig().lidarToCamera();
      const Eigen::Vector3d lidar_in_camera = lidar.col(3);
      const Eigen::Vector3d up_in_camera =
          dataset.rig().camera_in_body.linear().transpose() * Eigen::Vector3d::UnitZ();
      EXPECT_NEAR(lidar_in_camera.dot(up_in_camera), 0.6, 1e-9);
    }
  }
}

TEST(SyntheticScene, LidarBeamsAndFieldOfViewFollowTheVelodyneModel) {
  const double deg = M_PI / 180.0;
  for (const int beams : {16, 32, 64}) {
    SCOPED_TRACE(std::to_string(beams) + " beams");
    syn::SyntheticDatasetParams p = noiseFree(smallParams(9, 1));
    p.lidar = syn::LidarParams::velodyne(beams);
    p.lidar.range_sigma = 0.0;
    p.lidar.azimuth_step_deg = 1.0;
    const syn::SyntheticFrame f = syn::SyntheticDataset(p).frame(0);
    std::set<long> rings;
    double lowest = 90.0, highest = -90.0;
    for (const auto& r : f.lidar) {
      const double el = std::atan2(r.position.z(), r.position.head<2>().norm()) / deg;
      rings.insert(std::lround(el * 100.0));
      lowest = std::min(lowest, el);
      highest = std::max(highest, el);
    }
    EXPECT_EQ(rings.size(), static_cast<std::size_t>(beams));
    EXPECT_NEAR(lowest, p.lidar.elevation_min_deg, 1e-3);
    EXPECT_LE(highest, p.lidar.elevation_max_deg + 1e-3);
  }
  EXPECT_EQ(syn::LidarParams::velodyne(64).elevation_min_deg, syn::LidarParams().elevation_min_deg);
  EXPECT_THROW(syn::LidarParams::velodyne(20), multimodal_nvs::InputError);
}

TEST(SyntheticScene, RadarDensityAndClutterFollowTheirParameters) {
  auto returns = [](int candidates, double clutter) {
    syn::SyntheticDatasetParams p = smallParams(6, 1);
    p.radar.candidates = candidates;
    p.radar.clutter_fraction = clutter;
    const syn::SyntheticFrame f = syn::SyntheticDataset(p).frame(0);
    int ghosts = 0;
    for (const auto& r : f.radar)
      ghosts += r.clutter;
    return std::make_pair(static_cast<int>(f.radar.size()), ghosts);
  };
  const auto sparse = returns(300, 0.0), dense = returns(4000, 0.0);
  EXPECT_EQ(sparse.second, 0);
  EXPECT_GT(sparse.first, 10);
  EXPECT_GT(dense.first, 4 * sparse.first);
  const auto cluttered = returns(1600, 0.3);
  EXPECT_NEAR(double(cluttered.second) / cluttered.first, 0.3, 0.03);
}

TEST(SyntheticScene, OccludersStandWhereTheDriveSeesThemAndLeaveTheRestOfTheStreet) {
  syn::SyntheticDatasetParams p = smallParams(21, 4);
  const syn::SyntheticDataset plain(p);
  p.extra_vehicles = 8;
  p.pedestrians = 30;
  p.extra_poles = 12;
  const syn::SyntheticDataset busy(p);
  const auto& a = plain.scene().boxes();
  const auto& b = busy.scene().boxes();
  ASSERT_GT(b.size(), a.size() + 8 * 3 + 30 * 6);
  // The street without occluders is unchanged: the occluders come after it, from their own stream.
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].min, b[i].min) << "box " << i;
    ASSERT_EQ(a[i].material, b[i].material) << "box " << i;
  }
  const auto& layout = busy.scene().layout();
  EXPECT_EQ(layout.pedestrians, 30);
  int people = 0, striped = 0;
  for (std::size_t i = a.size(); i < b.size(); ++i) {
    const syn::Box& box = b[i];
    EXPECT_GE(box.max.x(), layout.occluder_min_x - 1.0);
    EXPECT_LE(box.min.x(), layout.occluder_max_x + 10.0);
    // Nothing stands in the ego lane where the drive passes (lane -3..0 m, up to the clear x).
    const bool in_ego_lane = box.max.y() > -layout.lane_width && box.min.y() < 0.0;
    if (in_ego_lane) {
      EXPECT_GE(box.max.x(), layout.ego_lane_clear_until_x) << "box " << i;
    }
    if (box.material == syn::Material::kSkin) ++people;
    if (box.material == syn::Material::kClothing && (box.variant & 1)) ++striped;
    EXPECT_LE(box.max.z(), 5.0);
  }
  EXPECT_EQ(people, 30);
  EXPECT_GT(striped, 0);
  // Pedestrians are seen: some camera pixels of the first frames show clothing or skin.
  int seen = 0;
  for (int i = 0; i < 4 && seen == 0; ++i) {
    const Eigen::Isometry3d cam = busy.cameraToOdom(i);
    const auto& k = busy.camera().intrinsics;
    for (int v = 0; v < busy.camera().size.height; ++v) {
      for (int u = 0; u < busy.camera().size.width; ++u) {
        const Eigen::Vector3d d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
        syn::Hit hit;
        const syn::Ray ray{cam.translation(), cam.linear() * d.normalized()};
        if (busy.scene().intersect(ray, hit)) {
          seen += hit.material == syn::Material::kClothing || hit.material == syn::Material::kSkin;
        }
      }
    }
  }
  EXPECT_GT(seen, 0);
}

TEST(SyntheticScene, ToolTakesTheSceneVariationsAndRejectsBadOnes) {
  const std::string root = freshDir("tool_variations");
  const auto ok = runTool("--output " + root +
                          " --scale 0.05 --num-frames 1 --quiet --lidar-azimuth-step 2 "
                          "--camera-height 2.2 --camera-pitch -4 --lidar-beams 16 "
                          "--radar-candidates 500 --radar-clutter 0.2 --vehicles 3 "
                          "--pedestrians 5 --poles 4 --speed 10 --radar-pass-through 0.9 "
                          "--radar-ghosts 0.4 --radar-ghost-max-factor 1.8 --radar-2d");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const std::string meta = readBytes(root + "/scene.json");
  for (const char* key :
       {"\"camera_height\": 2.2", "\"camera_pitch_deg\": -4", "\"lidar_beams\": 16",
        "\"radar_candidates\": 500", "\"pedestrians\": 5", "\"extra_poles\": 4",
        "\"extra_vehicles\": 3", "\"radar_pass_through\": 0.9", "\"radar_ghosts\": 0.4",
        "\"radar_ghost_range_factor_max\": 1.8", "\"radar_measures_elevation\": false"}) {
    EXPECT_NE(meta.find(key), std::string::npos) << key << " not in " << meta;
  }
  const struct {
    std::string args, expected;
    int code;
  } cases[] = {
      {"--lidar-beams 20", "--lidar-beams", 2},
      {"--camera-height 0.1", "camera height", 1},
      {"--camera-pitch 45", "camera pitch", 1},
      {"--pedestrians -1", "occluders", 1},
      {"--radar-pass-through 1.5", "--radar-pass-through", 2},
      {"--radar-ghost-max-factor 1.05", "--radar-ghost-max-factor", 2},
  };
  for (const auto& c : cases) {
    const auto r = runTool("--output " + root + " --scale 0.05 --num-frames 1 --quiet " + c.args);
    EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
}
