#pragma once
// Range returns in the camera's angular domain (azimuth, elevation, camera-z depth): the domain in
// which the local GP of the paper measures distances.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// A range sample expressed in the angular domain of the camera (degrees, elevation positive up)
/// with its camera-z depth. Angles are float32 because the reference stores them that way and the
/// neighbourhood test must see the very same values.
struct AngularSample {
  float azimuth_deg;
  float elevation_deg;
  float depth;
};

/// Camera-frame points -> angular samples: az = atan2(x, z), el = atan2(-y, hypot(x, z)), computed
/// in double and rounded to float32 (the reference's convention). Non-finite points are skipped and
/// counted in `dropped_non_finite` when it is not null; points behind the camera (z <= 0: depth
/// <= 0, 90 deg or more off the optical axis) are skipped. With a `pool`, chunks of the points are
/// converted in parallel and joined in order: the same samples in the same order.
std::vector<AngularSample> toAngularSamples(const std::vector<Eigen::Vector3d>& points_camera,
                                            std::size_t* dropped_non_finite = nullptr,
                                            ThreadPool* pool = nullptr);

/// Transforms sensor-frame points into the camera frame (double precision, like the reference).
std::vector<Eigen::Vector3d> transformToCamera(const std::vector<Eigen::Vector3f>& points_sensor,
                                               const SensorToCamera& sensor_to_camera);

/// An axis-aligned box in the angular domain (degrees).
struct AngularBox {
  float az_min, az_max, el_min, el_max;
};

/// The smallest box holding every sample's angles ({+inf, -inf, +inf, -inf} when there is none).
AngularBox boundingBox(const std::vector<AngularSample>& samples);

/// Samples with finite angles and a finite depth > 0, in their original order.
std::vector<AngularSample> usableSamples(const std::vector<AngularSample>& samples);

/// Continuous full-image pixel position (u, v) of the direction (az, el) in degrees — the inverse
/// of the pixel-angle convention: u = cx + fx tan(az), v = cy - fy tan(el) / cos(az), with the
/// camera's lens distortion applied to (tan(az), -tan(el) / cos(az)) when it has one. Returns false
/// for directions at or beyond 90 deg from the optical axis or past the distortion's valid range.
bool angularToPixel(const PinholeIntrinsics& k, double azimuth_deg, double elevation_deg, double* u,
                    double* v);

/// Azimuths (degrees) outside which no direction lands in the image columns [u_min, u_max]
/// (full-image pixels): through a pinhole lens a direction's column depends on its azimuth alone,
/// u = cx + fx tan(az), so a return far outside the window can be skipped before any tangent.
/// Widened by a margin far above the rounding of atan, so that the exact test after it decides;
/// with lens distortion (u depends on the elevation too) the whole front half, (-90, 90).
struct AzimuthWindow {
  double min_deg = -90.0, max_deg = 90.0;
  bool contains(double azimuth_deg) const {
    return azimuth_deg >= min_deg && azimuth_deg <= max_deg;  // false for NaN
  }
};
AzimuthWindow azimuthWindow(const PinholeIntrinsics& k, double u_min, double u_max);

/// The undistorted arithmetic of angularToPixel from the angles' tangents and cosine (radians),
/// for callers that reuse those terms across many projections (the triangulation's pixel boxes);
/// angularToPixel computes through these, so both give the same bits.
inline double pinholeColumn(const PinholeIntrinsics& k, double tan_az) {
  return k.cx + k.fx * tan_az;
}
inline double pinholeRow(const PinholeIntrinsics& k, double tan_el, double cos_az) {
  return k.cy - k.fy * tan_el / cos_az;
}

}  // namespace multimodal_nvs
