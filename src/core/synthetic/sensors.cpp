#include "multimodal_nvs/core/synthetic/sensors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace synthetic {

namespace {

constexpr double kDeg = M_PI / 180.0;

SensorToCamera toSensorToCamera(const Eigen::Isometry3d& sensor_to_camera) {
  return sensor_to_camera.matrix().topRows<3>();
}

/// Unit direction for azimuth (left of x, about z) and elevation (above the x-y plane).
Eigen::Vector3d direction(double azimuth, double elevation) {
  return Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                         std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
}

std::uint8_t toByte(float linear) {
  const double v = std::pow(std::min(1.0, std::max(0.0, static_cast<double>(linear))), 1.0 / 2.2);
  return static_cast<std::uint8_t>(std::lround(255.0 * v));
}

}  // namespace

SensorRig SensorRig::standard(double camera_height, double camera_pitch_deg) {
  SensorRig rig;
  Eigen::Matrix3d optical;
  optical.col(0) = -Eigen::Vector3d::UnitY();  // camera x: right
  optical.col(1) = -Eigen::Vector3d::UnitZ();  // camera y: down
  optical.col(2) = Eigen::Vector3d::UnitX();   // camera z: forward
  rig.camera_in_body = Eigen::Isometry3d::Identity();
  // Pitching up turns the optical axis (body x) towards body z: a negative turn about body y.
  rig.camera_in_body.linear() =
      Eigen::AngleAxisd(-camera_pitch_deg * kDeg, Eigen::Vector3d::UnitY()).matrix() * optical;
  rig.camera_in_body.translation() = Eigen::Vector3d(0.0, 0.0, camera_height);

  rig.radar_in_body = Eigen::Isometry3d::Identity();
  rig.radar_in_body.linear() = Eigen::AngleAxisd(-2.0 * kDeg, Eigen::Vector3d::UnitY()).matrix();
  rig.radar_in_body.translation() = Eigen::Vector3d(1.6, -0.2, 0.5);

  rig.lidar_in_body = Eigen::Isometry3d::Identity();
  rig.lidar_in_body.linear() = Eigen::AngleAxisd(1.0 * kDeg, Eigen::Vector3d::UnitZ()).matrix();
  rig.lidar_in_body.translation() = Eigen::Vector3d(-0.3, 0.0, camera_height + 0.6);
  return rig;
}

SensorToCamera SensorRig::radarToCamera() const {
  return toSensorToCamera(camera_in_body.inverse() * radar_in_body);
}

SensorToCamera SensorRig::lidarToCamera() const {
  return toSensorToCamera(camera_in_body.inverse() * lidar_in_body);
}

LidarParams LidarParams::velodyne(int beams) {
  LidarParams p;
  p.rings = beams;
  switch (beams) {
    case 64:
      break;
    case 32:
      p.elevation_max_deg = 10.67;
      p.elevation_min_deg = -30.67;
      break;
    case 16:
      p.elevation_max_deg = 15.0;
      p.elevation_min_deg = -15.0;
      break;
    default:
      throw InputError("LiDAR beams must be 16, 32 or 64, got " + std::to_string(beams));
  }
  return p;
}

CameraModel CameraModel::vod(double scale) {
  CameraModel m;
  m.size.width = std::max(1, static_cast<int>(std::lround(1936.0 * scale)));
  m.size.height = std::max(1, static_cast<int>(std::lround(1216.0 * scale)));
  m.intrinsics.fx = 1495.468642 * scale;
  m.intrinsics.fy = 1495.468642 * scale;
  m.intrinsics.cx = 961.272442 * scale;
  m.intrinsics.cy = 624.89592 * scale;
  return m;
}

Eigen::Isometry3d DrivePath::bodyPose(double t) const {
  const double w = 2.0 * M_PI / sway_period_s;
  const double x = start_x + speed * t;
  const double y = lane_y + sway * std::sin(w * t);
  const double heading = std::atan2(sway * w * std::cos(w * t), speed);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).matrix();
  pose.translation() = Eigen::Vector3d(x, y, 0.0);
  return pose;
}

CameraImage renderCamera(const SyntheticScene& scene, const CameraModel& camera,
                         const Eigen::Isometry3d& camera_to_world, int supersample,
                         ThreadPool& pool) {
  const int h = camera.size.height, w = camera.size.width;
  const int s = std::max(1, supersample);
  const PinholeIntrinsics& k = camera.intrinsics;
  CameraImage out;
  out.bgr.create(h, w, CV_8UC3);
  out.depth.create(h, w, CV_32FC1);
  const Eigen::Matrix3d r = camera_to_world.linear();
  const Eigen::Vector3d origin = camera_to_world.translation();
  const double pixel_angle = 1.0 / k.fx;

  // Neighbouring rays mostly hit the same box and are shadowed by the same caster: the hints
  // carry both along a row (they speed up the search, the result is the same).
  auto radiance = [&](double u, double v, double pixel, Hit& hit, bool& found, int& hint,
                      int& shadow_hint) {
    const Eigen::Vector3d d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
    const Ray ray{origin, r * d.normalized()};
    found = scene.intersect(ray, hit, 1e-6, -1.0, hint);
    if (found) hint = hit.box;
    return found ? scene.shade(ray, hit, pixel, &shadow_hint) : scene.sky(ray.direction);
  };

  // Pass 1: the centre ray of every pixel gives depth, a first colour and what was hit.
  std::vector<Eigen::Vector3f> colour(static_cast<std::size_t>(h) * w);
  std::vector<int> id(colour.size());
  pool.parallelFor(h, [&](long long row, int) {
    const int v = static_cast<int>(row);
    auto* depth = out.depth.ptr<float>(v);
    int hint = -1, shadow_hint = -1;
    for (int u = 0; u < w; ++u) {
      Hit hit;
      bool found = false;
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      colour[i] = radiance(u, v, pixel_angle, hit, found, hint, shadow_hint);
      const double norm = Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0).norm();
      depth[u] = found ? static_cast<float>(hit.t / norm) : 0.0f;
      id[i] = found ? hit.box : -2;
    }
  });

  // Pass 2 (adaptive anti-aliasing): pixels on an object boundary or a strong texture edge get
  // s x s rays. Reads only pass-1 results, so the output does not depend on the thread count.
  std::vector<std::uint8_t> refine(colour.size(), 0);
  if (s > 1) {
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * w + u;
        auto differs = [&](std::size_t j) {
          if (id[i] != id[j]) return true;
          const Eigen::Vector3f a = colour[i].cwiseMax(0.f).cwiseSqrt();
          const Eigen::Vector3f b = colour[j].cwiseMax(0.f).cwiseSqrt();
          return (a - b).cwiseAbs().maxCoeff() > 0.06f;
        };
        if ((u + 1 < w && differs(i + 1)) || (v + 1 < h && differs(i + w))) {
          refine[i] = 1;
          if (u + 1 < w) refine[i + 1] = 1;
          if (v + 1 < h) refine[i + w] = 1;
        }
      }
    }
  }
  pool.parallelFor(h, [&](long long row, int) {
    const int v = static_cast<int>(row);
    auto* bgr = out.bgr.ptr<cv::Vec3b>(v);
    int shadow_hint = -1;
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      Eigen::Vector3f c = colour[i];
      if (refine[i]) {
        c.setZero();
        int hint = id[i];
        for (int j = 0; j < s; ++j) {
          for (int q = 0; q < s; ++q) {
            Hit hit;
            bool found = false;
            c += radiance(u + (q + 0.5) / s - 0.5, v + (j + 0.5) / s - 0.5, pixel_angle / s, hit,
                          found, hint, shadow_hint);
          }
        }
        c /= static_cast<float>(s * s);
      }
      bgr[u] = cv::Vec3b(toByte(c.z()), toByte(c.y()), toByte(c.x()));
    }
  });
  return out;
}

std::vector<RadarReturn> simulateRadar(const SyntheticScene& scene,
                                       const Eigen::Isometry3d& radar_to_world,
                                       const Eigen::Vector3d& radar_velocity, const RadarParams& p,
                                       Random& rng) {
  std::vector<RadarReturn> returns;
  const Eigen::Matrix3d r = radar_to_world.linear();
  const Eigen::Vector3d origin = radar_to_world.translation();
  const double az_max = p.azimuth_fov_deg * kDeg;
  const double el_min = p.elevation_min_deg * kDeg, el_max = p.elevation_max_deg * kDeg;
  std::set<std::array<long, 3>> cells;

  auto finish = [&](RadarReturn& ret, const Eigen::Vector3d& measured_dir) {
    // Radial velocity of a static point seen from the moving radar, and its ego-compensated value.
    const double ego_radial = -measured_dir.dot(radar_velocity);
    ret.v_r = static_cast<float>(ego_radial + p.velocity_sigma * rng.normal());
    ret.v_r_compensated = static_cast<float>(ret.v_r - ego_radial);
    ret.time = 0.0f;
  };

  for (int c = 0; c < p.candidates; ++c) {
    const double az = rng.uniform(-az_max, az_max);
    const double el = rng.uniform(el_min, el_max);
    const double detect_draw = rng.uniform();
    const Eigen::Vector3d local = direction(az, el);
    Ray ray{origin, r * local};
    Hit hit;
    if (!scene.intersect(ray, hit, 1e-6, p.max_range) || hit.t < p.min_range) continue;
    const double incidence = std::abs(hit.normal.dot(ray.direction));
    const double probability = SyntheticScene::radarReflectivity(hit.material) *
                               (0.3 + 0.7 * incidence) * (1.0 - 0.5 * hit.t / p.max_range);
    if (detect_draw >= probability) continue;
    // Drawn only when asked, so that scenes made without it keep their random sequence.
    if (p.pass_through > 0.0 && rng.uniform() < p.pass_through) {
      const Ray behind{hit.point + 1e-3 * ray.direction, ray.direction};
      Hit next;
      if (!scene.intersect(behind, next, 1e-6, p.max_range - hit.t)) continue;
      next.t += hit.t + 1e-3;
      hit = next;
    }
    // A multipath ghost: the same beam, a longer echo path (drawn only when asked, as above).
    double path = hit.t;
    const bool ghost = p.ghosts > 0.0 && rng.uniform() < p.ghosts;
    if (ghost) {
      path = hit.t * rng.uniform(kMinGhostRangeFactor, p.ghost_range_factor_max);
      if (path > p.max_range) continue;
    }
    // One detection per resolution cell (azimuth x elevation x range), as a radar resolves them.
    const std::array<long, 3> cell{std::lround(az / (p.azimuth_cell_deg * kDeg)),
                                   std::lround(el / (p.elevation_cell_deg * kDeg)),
                                   std::lround(path / p.range_cell)};
    if (!cells.insert(cell).second) continue;
    const double range = path + p.range_sigma * rng.normal();
    const double az_m = az + p.azimuth_sigma_deg * kDeg * rng.normal();
    const double el_m = el + p.elevation_sigma_deg * kDeg * rng.normal();
    // A 2D radar reports the detection on its own scan plane: the elevation is drawn (the same
    // random sequence) but not measured.
    const Eigen::Vector3d measured = direction(az_m, p.measures_elevation ? el_m : 0.0);
    RadarReturn ret;
    ret.position = (range * measured).cast<float>();
    ret.rcs = static_cast<float>(SyntheticScene::radarCrossSectionDb(hit.material) +
                                 10.0 * std::log10(std::max(0.05, incidence)) +
                                 p.rcs_sigma_db * rng.normal());
    ret.true_range = hit.t;
    ret.ghost = ghost;
    finish(ret, measured);
    returns.push_back(ret);
  }

  // Clutter: multipath and noise returns anywhere in the field of view, weak and on no surface.
  const double f = std::min(0.9, std::max(0.0, p.clutter_fraction));
  const int clutter = static_cast<int>(std::lround(returns.size() * f / (1.0 - f)));
  for (int i = 0; i < clutter; ++i) {
    // One expression as it always was, so that the random draws keep their order (the order of
    // a call's arguments is the compiler's), then flattened for a 2D radar.
    const Eigen::Vector3d drawn =
        direction(rng.uniform(-az_max, az_max), rng.uniform(el_min, el_max));
    const Eigen::Vector3d d =
        p.measures_elevation ? drawn : direction(std::atan2(drawn.y(), drawn.x()), 0.0);
    RadarReturn ret;
    ret.position = (rng.uniform(2.0, 0.75 * p.max_range) * d).cast<float>();
    ret.rcs = static_cast<float>(-18.0 + 4.0 * rng.normal());
    ret.clutter = true;
    finish(ret, d);
    ret.v_r += static_cast<float>(0.5 * rng.normal());  // multipath ghosts move oddly
    ret.v_r_compensated = static_cast<float>(ret.v_r + d.dot(radar_velocity));
    returns.push_back(ret);
  }
  // Interleave the clutter like a real scan list.
  for (std::size_t i = returns.size(); i > 1; --i) {
    std::swap(returns[i - 1], returns[static_cast<std::size_t>(rng.index(static_cast<int>(i)))]);
  }
  return returns;
}

std::vector<LidarReturn> simulateLidar(const SyntheticScene& scene,
                                       const Eigen::Isometry3d& lidar_to_world,
                                       const LidarParams& p, std::uint64_t seed, ThreadPool& pool) {
  const int columns = std::max(1, static_cast<int>(std::lround(360.0 / p.azimuth_step_deg)));
  const int rings = std::max(1, p.rings);
  std::vector<std::vector<LidarReturn>> per_column(columns);
  const Eigen::Matrix3d r = lidar_to_world.linear();
  const Eigen::Vector3d origin = lidar_to_world.translation();

  pool.parallelFor(columns, [&](long long col, int) {
    Random rng = Random::derived(seed, static_cast<std::uint64_t>(col));
    // The scan starts behind the sensor and turns counter-clockwise, like a Velodyne.
    const double az = -M_PI + (col + 0.5) * 2.0 * M_PI / columns;
    auto& out = per_column[col];
    out.reserve(rings);
    int hint = -1;
    for (int ring = 0; ring < rings; ++ring) {
      const double el = (p.elevation_min_deg + (p.elevation_max_deg - p.elevation_min_deg) * ring /
                                                   std::max(1, rings - 1)) *
                        kDeg;
      const double noise = rng.normal();
      const double drop = rng.uniform();
      const double speckle = rng.normal();
      const Eigen::Vector3d local = direction(az, el);
      Ray ray{origin, r * local};
      Hit hit;
      if (!scene.intersect(ray, hit, 1e-6, p.max_range, hint)) continue;
      hint = hit.box;
      if (hit.t < p.min_range || drop < p.dropout) continue;
      const double incidence = std::abs(hit.normal.dot(ray.direction));
      const double range = hit.t + p.range_sigma * noise;
      LidarReturn ret;
      ret.position = (range * local).cast<float>();
      const double intensity =
          255.0 * scene.lidarReflectivity(hit) * (0.3 + 0.7 * incidence) + 3.0 * speckle;
      ret.intensity = static_cast<float>(std::round(std::min(255.0, std::max(1.0, intensity))));
      out.push_back(ret);
    }
  });
  std::vector<LidarReturn> all;
  std::size_t total = 0;
  for (const auto& c : per_column)
    total += c.size();
  all.reserve(total);
  for (const auto& c : per_column)
    all.insert(all.end(), c.begin(), c.end());
  return all;
}

}  // namespace synthetic
}  // namespace multimodal_nvs
