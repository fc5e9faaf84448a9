#include "multimodal_nvs/core/depth/angular_samples.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace multimodal_nvs {
namespace {
// numpy's degrees(): x * (180/pi) with the constant formed in the operand's precision.
constexpr double kRadToDeg64 = 180.0 / 3.14159265358979323846;
}  // namespace

std::vector<Eigen::Vector3d> transformToCamera(const std::vector<Eigen::Vector3f>& points_sensor,
                                               const SensorToCamera& sensor_to_camera) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(points_sensor.size());
  const Eigen::Matrix3d rotation = sensor_to_camera.leftCols<3>();
  const Eigen::Vector3d translation = sensor_to_camera.col(3);
  for (const auto& p : points_sensor)
    out.emplace_back(rotation * p.cast<double>() + translation);
  return out;
}

namespace {

/// Appends the samples of points [begin, end) to `out`; returns the non-finite points skipped.
std::size_t appendAngularSamples(const Eigen::Vector3d* begin, const Eigen::Vector3d* end,
                                 std::vector<AngularSample>& out) {
  std::size_t dropped = 0;
  for (const Eigen::Vector3d* it = begin; it != end; ++it) {
    const Eigen::Vector3d& p = *it;
    if (!p.allFinite()) {
      ++dropped;
      continue;
    }
    // Behind the camera (or in its plane): depth <= 0, which the shift, the ground fit and every
    // depth test ignore, and 90 deg or more off the optical axis, beyond any neighbourhood of a
    // camera's pixels. Skipped before the two atan2: half of a 360-degree LiDAR sweep.
    if (!(p.z() > 0.0)) continue;
    const double az = std::atan2(p.x(), p.z()) * kRadToDeg64;
    const double el = std::atan2(-p.y(), std::sqrt(p.x() * p.x() + p.z() * p.z())) * kRadToDeg64;
    out.push_back({static_cast<float>(az), static_cast<float>(el), static_cast<float>(p.z())});
  }
  return dropped;
}

// Two double atan2 per point: ~8 ms for a 167 k-point HDL-64 scan on one core, so a LiDAR scan is
// split over the pool.
constexpr std::size_t kPointsPerChunk = 16384;

}  // namespace

std::vector<AngularSample> toAngularSamples(const std::vector<Eigen::Vector3d>& points_camera,
                                            std::size_t* dropped_non_finite, ThreadPool* pool) {
  std::vector<AngularSample> out;
  const std::size_t n = points_camera.size();
  const Eigen::Vector3d* points = points_camera.data();
  std::size_t dropped = 0;
  const std::size_t chunks = (n + kPointsPerChunk - 1) / kPointsPerChunk;
  if (pool == nullptr || pool->size() == 1 || chunks < 2) {
    out.reserve(n);
    dropped = appendAngularSamples(points, points + n, out);
  } else {
    std::vector<std::vector<AngularSample>> parts(chunks);
    std::vector<std::size_t> part_dropped(chunks);
    pool->parallelFor(static_cast<long long>(chunks), [&](long long c, int) {
      const std::size_t begin = std::size_t(c) * kPointsPerChunk;
      const std::size_t end = std::min(n, begin + kPointsPerChunk);
      parts[c].reserve(end - begin);
      part_dropped[c] = appendAngularSamples(points + begin, points + end, parts[c]);
    });
    std::size_t total = 0;
    for (std::size_t c = 0; c < chunks; ++c) {
      total += parts[c].size();
      dropped += part_dropped[c];
    }
    out.reserve(total);
    for (const auto& part : parts)
      out.insert(out.end(), part.begin(), part.end());
  }
  if (dropped_non_finite != nullptr) *dropped_non_finite = dropped;
  return out;
}

AngularBox boundingBox(const std::vector<AngularSample>& samples) {
  float az0 = std::numeric_limits<float>::infinity(), az1 = -az0, el0 = az0, el1 = -az0;
  for (const AngularSample& s : samples) {
    az0 = std::min(az0, s.azimuth_deg);
    az1 = std::max(az1, s.azimuth_deg);
    el0 = std::min(el0, s.elevation_deg);
    el1 = std::max(el1, s.elevation_deg);
  }
  return {az0, az1, el0, el1};
}

std::vector<AngularSample> usableSamples(const std::vector<AngularSample>& samples) {
  std::vector<AngularSample> out;
  out.reserve(samples.size());
  for (const AngularSample& s : samples) {
    if (std::isfinite(s.azimuth_deg) && std::isfinite(s.elevation_deg) && std::isfinite(s.depth) &&
        s.depth > 0.0f) {
      out.push_back(s);
    }
  }
  return out;
}

AzimuthWindow azimuthWindow(const PinholeIntrinsics& k, double u_min, double u_max) {
  AzimuthWindow window;
  if (k.distortion.any() || !(k.fx > 0.0)) return window;
  constexpr double kMarginDeg = 1e-3;
  window.min_deg = std::atan((u_min - k.cx) / k.fx) * kRadToDeg64 - kMarginDeg;
  window.max_deg = std::atan((u_max - k.cx) / k.fx) * kRadToDeg64 + kMarginDeg;
  return window;
}

bool angularToPixel(const PinholeIntrinsics& k, double azimuth_deg, double elevation_deg, double* u,
                    double* v) {
  constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
  if (!(std::abs(azimuth_deg) < 90.0) || !(std::abs(elevation_deg) < 90.0)) return false;
  const double az = azimuth_deg * kDegToRad, el = elevation_deg * kDegToRad;
  if (k.distortion.any()) {
    double xd = 0, yd = 0;
    if (!k.distortion.distort(std::tan(az), -std::tan(el) / std::cos(az), &xd, &yd)) return false;
    *u = k.cx + k.fx * xd;
    *v = k.cy + k.fy * yd;
    return true;
  }
  *u = pinholeColumn(k, std::tan(az));
  *v = pinholeRow(k, std::tan(el), std::cos(az));
  return true;
}

}  // namespace multimodal_nvs
