// How the cost of the default models grows: compute time of the default radar model
// (config/radar.yaml) against the radar returns in view (100, 300, 1,000, 3,000) at its configured
// stride and at stride 1, of the default LiDAR model (config/lidar.yaml) against the LiDAR returns
// in view (5k, 25k, 100k) at full resolution, and of both against the image size (0.25, 0.5, 1 x
// the pixels of VoD's 1936x1216 camera). The scans are synthetic, made here so that the count in
// view is exact: rays from the camera hit a road plane, parked cars and house fronts along a street
// and a far wall (the sky returns nothing). Radar: uniformly random pixels; LiDAR: 64 rings of an
// HDL-64
// (-24.8..+2 deg), the azimuth step chosen for the requested count. The model parameters are read
// from the YAML files (model, ground_input, max_neighbors, approx_tile, retain_percent, stride,
// ground pose), so the table follows the shipped defaults. Run: scripts/bench_scaling.sh.
#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <vector>

#include "benchmark_main.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/synthetic/sensors.hpp"

namespace mm = multimodal_nvs;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The default model of a config file and its stride.
struct DefaultModel {
  mm::DepthCompletionParams params;
  int stride = 1;
};

DefaultModel loadDefaultModel(const std::string& name) {
  const YAML::Node yaml = YAML::LoadFile(std::string(MMNVS_SOURCE_DIR) + "/config/" + name);
  DefaultModel m;
  mm::DepthCompletionParams& p = m.params;
  p.model = mm::parseDepthModel(yaml["model"].as<std::string>());
  if (yaml["ground_input"])
    p.ground.input = mm::parseGroundInput(yaml["ground_input"].as<std::string>());
  if (yaml["max_neighbors"]) p.max_neighbors = yaml["max_neighbors"].as<int>();
  if (yaml["approx_tile"]) p.approx_tile = yaml["approx_tile"].as<int>();
  if (yaml["retain_percent"]) p.retain_percent = yaml["retain_percent"].as<double>();
  if (yaml["radius_deg"]) p.radius_deg = yaml["radius_deg"].as<double>();
  if (yaml["threads"]) p.threads = yaml["threads"].as<int>();
  if (yaml["stride"]) m.stride = yaml["stride"].as<int>();
  // The ground pose as the node maps it (ros/depth_completion_config.cpp).
  const double height = yaml["ground_camera_height"] ? yaml["ground_camera_height"].as<double>()
                                                     : p.ground.camera_height;
  const double pitch =
      (yaml["ground_pitch_deg"] ? yaml["ground_pitch_deg"].as<double>() : 0.0) * kPi / 180.0;
  p.ground.camera_height = height;
  p.ground.up_x = 0.0;
  p.ground.up_y = -std::cos(pitch);
  p.ground.up_z = std::sin(pitch);
  return m;
}

/// A street in a frame with x right, y forward, z up, the camera at the origin `height` above the
/// road: parked cars on both sides, house fronts 7 m left and right, a wall 80 m ahead, 12 m high.
class Street {
 public:
  explicit Street(const mm::GroundPriorParams& ground) : height_(ground.camera_height) {
    up_ = Eigen::Vector3d(ground.up_x, ground.up_y, ground.up_z).normalized();
    forward_ = (Eigen::Vector3d::UnitZ() - up_.z() * up_).normalized();
    right_ = forward_.cross(up_);
    for (double y = 6.0; y < 60.0; y += 7.5) {
      addBox({-3.9, y, -height_}, {-2.1, y + 4.5, 1.5 - height_});
      addBox({2.4, y + 3.0, -height_}, {4.2, y + 7.5, 1.6 - height_});
    }
    addBox({-30.0, 0.5, -height_}, {-7.0, 80.0, 9.0 - height_});
    addBox({7.0, 0.5, -height_}, {30.0, 80.0, 11.0 - height_});
    addBox({-30.0, 80.0, -height_}, {30.0, 81.0, 12.0 - height_});
  }

  /// Camera-frame point where the ray along `dir` (camera frame) first hits the street; false for
  /// the sky.
  bool hit(const Eigen::Vector3d& dir, Eigen::Vector3d* point) const {
    const Eigen::Vector3d d(dir.dot(right_), dir.dot(forward_), dir.dot(up_));
    double best = std::numeric_limits<double>::infinity();
    if (d.z() < 0.0) best = -height_ / d.z();
    for (const auto& box : boxes_) {
      double t0 = 0.0, t1 = best;
      for (int a = 0; a < 3 && t0 <= t1; ++a) {
        if (std::abs(d[a]) < 1e-12) {
          if (box.first[a] > 0.0 || box.second[a] < 0.0) t0 = t1 + 1.0;
          continue;
        }
        double ta = box.first[a] / d[a], tb = box.second[a] / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (t0 <= t1 && t0 > 0.0) best = std::min(best, t0);
    }
    if (!std::isfinite(best)) return false;
    *point = best * dir;
    return true;
  }

  Eigen::Vector3d up() const { return up_; }
  Eigen::Vector3d forward() const { return forward_; }
  Eigen::Vector3d right() const { return right_; }

 private:
  void addBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) { boxes_.push_back({lo, hi}); }

  double height_;
  Eigen::Vector3d up_, forward_, right_;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes_;
};

bool inView(const Eigen::Vector3d& p, const mm::PinholeIntrinsics& k, const mm::ImageSize& size) {
  double u = 0, v = 0;
  if (!(p.z() > 0.0) || !k.project(p.x(), p.y(), p.z(), &u, &v)) return false;
  return u >= 0.0 && v >= 0.0 && u < size.width && v < size.height;
}

/// `count` radar returns in view: rays through uniformly random pixels that hit the street.
std::vector<Eigen::Vector3d> radarScan(const Street& street, const mm::synthetic::CameraModel& cam,
                                       int count) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, cam.size.width), v(0.0, cam.size.height);
  const mm::PinholeIntrinsics& k = cam.intrinsics;
  std::vector<Eigen::Vector3d> points;
  while (static_cast<int>(points.size()) < count) {
    const double x = u(rng), y = v(rng);
    Eigen::Vector3d p;
    if (street.hit({(x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0}, &p)) points.push_back(p);
  }
  return points;
}

/// An HDL-64-like scan (64 rings, -24.8..+2 deg about the horizon) whose azimuth step puts about
/// `count` returns in view (the step is found from a trial scan; the sky returns nothing).
std::vector<Eigen::Vector3d> lidarScan(const Street& street, const mm::synthetic::CameraModel& cam,
                                       int count) {
  auto scan = [&](double step_deg) {
    std::vector<Eigen::Vector3d> points;
    for (int ring = 0; ring < 64; ++ring) {
      const double el = (-24.8 + ring * 26.8 / 63.0) * kPi / 180.0;
      for (double az = -60.0; az <= 60.0; az += step_deg) {
        const double a = az * kPi / 180.0;
        const Eigen::Vector3d dir =
            std::cos(el) * (std::cos(a) * street.forward() + std::sin(a) * street.right()) +
            std::sin(el) * street.up();
        Eigen::Vector3d p;
        if (street.hit(dir, &p) && inView(p, cam.intrinsics, cam.size)) points.push_back(p);
      }
    }
    return points;
  };
  const double trial_step = 0.2;
  const std::size_t trial = scan(trial_step).size();
  return scan(trial_step * double(trial) / count);
}

/// A camera image of the street for image_guided (its smoother's edges and its sky test read it):
/// grey levels falling with the depth of the surface each pixel's ray hits, bright where it hits
/// nothing (the sky). The smoother's cost does not depend on the content; the sky test's does a
/// little.
cv::Mat streetImage(const Street& street, const mm::synthetic::CameraModel& cam) {
  const mm::PinholeIntrinsics& k = cam.intrinsics;
  cv::Mat image(cam.size.height, cam.size.width, CV_8UC3);
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      Eigen::Vector3d p;
      const bool hit = street.hit({(u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0}, &p);
      const auto grey =
          static_cast<std::uint8_t>(hit ? std::clamp(800.0 / (4.0 + p.z()), 20.0, 200.0) : 230.0);
      image.at<cv::Vec3b>(v, u) = cv::Vec3b(grey, grey, grey);
    }
  }
  return image;
}

/// Runs the default model of `config` on a synthetic scan; args: returns in view, stride (0: the
/// config's), image pixels in percent of VoD's.
void runScaling(benchmark::State& state, const std::string& config, bool lidar) {
  const DefaultModel model = loadDefaultModel(config);
  const int count = static_cast<int>(state.range(0));
  const int stride = state.range(1) > 0 ? static_cast<int>(state.range(1)) : model.stride;
  const double scale = std::sqrt(state.range(2) / 100.0);
  const auto camera = mm::synthetic::CameraModel::vod(scale);
  const Street street(model.params.ground);
  const std::vector<Eigen::Vector3d> points =
      lidar ? lidarScan(street, camera, count) : radarScan(street, camera, count);
  const mm::StrideGrid grid{camera.size, stride};
  const cv::Mat image =
      model.params.model == mm::DepthModel::kImageGuided ? streetImage(street, camera) : cv::Mat();
  mm::DepthCompleter completer(model.params.threads);
  mm::DepthMap map;  // reused across scans, as a node does
  completer.complete(points, camera.intrinsics, grid, model.params, map, image);  // camera setup
  for (auto _ : state) {
    completer.complete(points, camera.intrinsics, grid, model.params, map, image);
    benchmark::DoNotOptimize(map.depth.data());
  }
  state.counters["in_view"] = static_cast<double>(map.stats.points_in_view);
  state.counters["stride"] = stride;
  state.counters["grid_px"] = static_cast<double>(map.stats.pixels);
  state.counters["sets"] = static_cast<double>(map.stats.neighbour_sets);
}

void BM_RadarDefault(benchmark::State& state) {
  runScaling(state, "radar.yaml", false);
}
void BM_LidarDefault(benchmark::State& state) {
  runScaling(state, "lidar.yaml", true);
}

}  // namespace

// Arguments: returns in view, stride (0: the config's), image pixels (% of VoD's 1936x1216).
BENCHMARK(BM_RadarDefault)
    ->ArgNames({"points", "stride", "image_pct"})
    ->ArgsProduct({{100, 300, 1000, 3000}, {0, 1}, {100}})
    ->ArgsProduct({{1000}, {0, 1}, {25, 50}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(0.5);
BENCHMARK(BM_LidarDefault)
    ->ArgNames({"points", "stride", "image_pct"})
    ->ArgsProduct({{5000, 25000, 100000}, {1}, {100}})
    ->ArgsProduct({{25000}, {1}, {25, 50}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(0.5);

int main(int argc, char** argv) {
  return multimodal_nvs::runBenchmarks(argc, argv);
}
