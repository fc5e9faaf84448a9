#pragma once
// The priors of ground_gp: the ground plane and the nearest surface seen along each pixel ray.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/surface_colours.hpp"

namespace multimodal_nvs {

/// The ground as seen from the camera: the plane {X : up . X = -height} in the camera optical
/// frame, with `up` the unit world-up direction expressed in camera coordinates.
struct GroundPlane {
  Eigen::Vector3d up{0.0, -1.0, 0.0};  ///< level camera: world up is camera -y
  double height = 1.3;                 ///< camera height above the ground, metres

  /// From a camera-to-world pose whose world z axis points up and whose z = 0 is the ground
  /// (VoD's odomToCamera/mapToCamera poses).
  static GroundPlane fromCameraToWorld(const Eigen::Matrix4d& camera_to_world);

  /// The plane of a camera `height` m above the road, its optical axis `pitch_deg` above it and
  /// rolled `roll_deg` (the conventions of pitchDeg and rollDeg, whose inverse this is).
  static GroundPlane fromAngles(double height, double pitch_deg, double roll_deg);

  /// Corners of a rectangle of the road in the camera frame, for display: from `near` to `far`
  /// metres ahead along the road (the optical axis projected onto the plane) and `half_width`
  /// metres to either side; near-left, near-right, far-right, far-left. Needs an optical axis
  /// that is not along up (any camera that sees the road).
  std::array<Eigen::Vector3d, 4> patchCorners(double near, double far, double half_width) const;

  /// The optical axis's angle above the road plane, degrees (positive: looking up; the convention
  /// of the ground_pitch_deg parameter).
  double pitchDeg() const { return std::asin(std::clamp(up.z(), -1.0, 1.0)) * 180.0 / M_PI; }
  /// The camera's roll about its optical axis, degrees: positive when world up leans towards the
  /// image's +x (right).
  double rollDeg() const { return std::atan2(up.x(), -up.y()) * 180.0 / M_PI; }

  /// Camera-z depth where the ray through normalised image point (x, y) = (X/Z, Y/Z) meets the
  /// ground, or +inf when the ray does not descend.
  double depthAlong(double x, double y) const {
    const double descent = up.x() * x + up.y() * y + up.z();
    return descent < 0.0 ? -height / descent : INFINITY;
  }
};

/// Normalised image coordinates (X/Z, Y/Z) of an angular direction (az, el in degrees).
Eigen::Vector2d normalisedFromAngles(double azimuth_deg, double elevation_deg);

/// The prior depth of every grid pixel: ground depth below the horizon, capped at `far_depth`
/// (also above the horizon, where there is no ground). Rows on `pool` when given.
std::vector<float> groundPriorDepth(const PixelAngleGrid& angles, const GroundPlane& plane,
                                    double far_depth, ThreadPool* pool = nullptr);

/// groundPriorDepth a row at a time, the same values: for a pass that consumes the prior row by
/// row and need not hold (write, then read back) the full-size plane. Holds a reference to
/// `angles`.
class GroundPriorRows {
 public:
  GroundPriorRows(const PixelAngleGrid& angles, const GroundPlane& plane, double far_depth);
  /// Row `r`'s prior (the grid's cols() floats) into `out`.
  void row(int r, float* out) const;

 private:
  const PixelAngleGrid& angles_;
  GroundPlane plane_;
  double far_depth_;
  std::vector<double> column_x_;  // a pinhole camera's normalised x per column
};
/// groundPriorDepth of one grid pixel (row r, column c), the same arithmetic: for passes that need
/// the ground at some pixels only. Inline: such passes call it for a million pixels.
inline float groundPriorDepthAt(const PixelAngleGrid& angles, const GroundPlane& plane, int r,
                                int c, double far_depth) {
  double x = 0.0, y = 0.0;
  if (angles.distorted()) {  // the undistorted rays, from the grid's table
    const Eigen::Vector2d ray = angles.normalisedRay(r, c);
    x = ray.x();
    y = ray.y();
  } else {  // pixel rays straight from the intrinsics
    const PinholeIntrinsics& k = angles.intrinsics();
    const int stride = angles.grid().stride;
    x = (c * stride - k.cx) / k.fx;
    y = (r * stride - k.cy) / k.fy;
  }
  return static_cast<float>(std::min(plane.depthAlong(x, y), far_depth));
}

/// The nearest-surface depth of every grid pixel: the `rank`-th smallest depth (1 = smallest)
/// among the `k` samples angularly nearest to the pixel, and the angular distance (degrees) to
/// the nearest sample. A far return behind a near one (radar multipath, returns through
/// vegetation) does not pull this estimate, unlike a mean. Evaluated on a lattice every `step`
/// grid pixels and interpolated bilinearly in between. Empty samples: +inf depth.
/// With `support`, distance_deg is the distance to the nearest of those samples instead (same
/// lattice pass: ground_gp needs the surface of the object returns and the distance to any return).
struct NearestSurface {
  std::vector<float> depth;
  std::vector<float> distance_deg;
};
NearestSurface nearestSurfaceDepth(const std::vector<AngularSample>& samples,
                                   const PixelAngleGrid& angles, int k, int rank, int step,
                                   ThreadPool& pool,
                                   const std::vector<AngularSample>* support = nullptr);

/// nearestSurfaceDepth before its interpolation between lattice rows: the lattice rows
/// interpolated along every grid column. A caller with its own full-image pass (ground_gp's sparse
/// mode) finishes the interpolation there, instead of writing and re-reading two full-resolution
/// arrays. Same arithmetic, so the same values as nearestSurfaceDepth.
struct NearestSurfaceRows {
  int cols = 0, step = 1;
  bool has_depth = false;      ///< false without samples: depth() is +inf everywhere
  std::vector<int> node_rows;  ///< grid rows of the lattice (every step-th and the last)
  std::vector<float> depth_rows, distance_rows;  ///< node_rows.size() x cols

  /// Where grid row r lies: between lattice rows `lower` and `lower + 1` (clamped) at weight t.
  struct RowWeights {
    const float* depth_lo;
    const float* depth_hi;
    const float* distance_lo;
    const float* distance_hi;
    float t;
  };
  RowWeights row(int r) const;
  static float lerp(float lo, float hi, float t) { return (1 - t) * lo + t * hi; }
  float depth(int r, int c) const {
    if (!has_depth) return INFINITY;
    const RowWeights w = row(r);
    return lerp(w.depth_lo[c], w.depth_hi[c], w.t);
  }
};
/// With `image.colours`, each of the k samples counts by the resemblance of its pixel's colour to
/// the lattice node's (SurfaceColours::weight) and the rank-th smallest becomes the depth at which
/// the depth-sorted weight reaches (rank - 0.5) / k of the total: a surface that looks like the
/// pixel decides, not the nearest of another colour (a parked car's returns for the facade above);
/// with `image.walls` that sample, when it looks like the node, continues as a wall along the view
/// (wallDepth).
NearestSurfaceRows nearestSurfaceRows(const std::vector<AngularSample>& samples,
                                      const PixelAngleGrid& angles, int k, int rank, int step,
                                      ThreadPool& pool,
                                      const std::vector<AngularSample>* support = nullptr,
                                      const SurfacePriorImage& image = SurfacePriorImage{});

}  // namespace multimodal_nvs
