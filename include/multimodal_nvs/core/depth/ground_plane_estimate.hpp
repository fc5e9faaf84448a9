#pragma once
// The ground plane from the returns themselves (RANSAC), and which plane ground_gp uses: the one
// the returns show when they show one, else the pose's (tf or a pose file), else the parameters.
#include <cstddef>
#include <vector>

#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// A RANSAC plane through the returns in view, near the expected ground.
struct GroundPlaneFit {
  bool found = false;            ///< a plausible plane (see estimateGroundPlane)
  GroundPlane plane;             ///< valid when found
  std::size_t returns = 0;       ///< returns considered (in view, within the range)
  std::size_t inliers = 0;       ///< of those, within the distance threshold of the plane
  double inlier_fraction = 0.0;  ///< inliers / returns (0 without returns)
  /// The returns in view (at least 12, any range) lie within 5 cm RMS of one plane: a 2D
  /// scanner's (e.g. nuScenes' radar), whose elevation (and so pixel row) is not measured.
  bool single_scan_plane = false;
};

/// Fits the ground by RANSAC (the normal within 20 deg of `expected.up`, then least squares on the
/// inliers) on the returns in view within 40 m; deterministic. `found` requires at least
/// min_returns returns spread over at least min_elevation_spread degrees of elevation (a 2D
/// scanner's returns are all on its own scan plane, which is not the ground), a camera height in
/// [min_height, max_height] and few returns clearly below the plane (nothing is seen through the
/// road). The inlier fraction is reported either way: it tells LiDAR-precise returns (a quarter to
/// most of them on the road within 10 cm) from radar returns (a few per cent; their elevation is
/// coarse).
GroundPlaneFit estimateGroundPlane(const std::vector<AngularSample>& samples,
                                   const PixelAngleGrid& angles, const GroundPlane& expected,
                                   const GroundPriorParams& params);

/// What ground_gp uses, and why (reported in the depth stats and the nodelet's diagnostics).
struct GroundChoice {
  GroundPlane plane;
  GroundPriorParams::PlaneSource source = GroundPriorParams::PlaneSource::kParameters;
  bool dense = false;            ///< the dense (interpolating) mode, else the sparse (radar) one
  double inlier_fraction = 0.0;  ///< of the RANSAC fit (0 when not fitted)
  /// Share of the returns in view whose nearest other return lies along the image rows (within
  /// 20 deg of horizontal): ~0.2 for scattered returns (radar), 0.5-1 for a scanning LiDAR's rings.
  /// Computed only when the mode is judged from the returns and neither a low inlier fraction
  /// nor a precise fit with dense returns decides it (else -1).
  double scan_line_share = -1.0;
  bool plane_fitted = false;  ///< a fit was attempted and gave a plausible plane
  /// Sparse mode: the residual GP ran the tile approximation (large neighbour sets), not the exact
  /// one (set by predictWithModel).
  bool tiled_residual = false;
  /// Dense mode: returns left out as hidden from the camera (-1: the filter did not run; set by
  /// predictWithModel).
  long long hidden_returns = -1;
  /// Dense mode: the relative depth step that separated surfaces (denseEdgeRatio; -1 in the other
  /// modes; set by predictWithModel).
  double edge_ratio = -1.0;
  /// The returns lie on one scan plane (GroundPlaneFit::single_scan_plane; false when no fit ran):
  /// the pixel a return projects to is not where it was seen, so its colour says nothing.
  bool single_scan_plane = false;
};

/// The plane given by the parameters (camera_height and up, which a pose or tf may have set).
GroundPlane givenGroundPlane(const GroundPriorParams& params);

/// The plane and the mode of ground_gp for these returns. Plane: the returns' RANSAC plane when
/// params.estimate_plane and the fit holds at least precise_fraction of the returns and at least
/// 80 of them (a quarter of a few dozen scattered returns lies on some plane by chance), else the
/// given one (params.plane_source says whether a pose or the parameters gave it). Mode
/// (params.input auto): dense when the returns are LiDAR-precise (that same test, and their mean
/// spacing at most params.radius_deg or most of them on scan lines: a radar mounted high also fits
/// the road well) or when they lie on scan lines (scanLineShare >= 0.4) with at least 10 % of them
/// on the ground plane; sparse when a fit was possible and neither holds; without a possible fit
/// (too few returns, or all on one scan plane) the mean-spacing rule of groundInputIsDense decides.
GroundChoice chooseGround(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                          const DepthCompletionParams& params);

/// Share of the returns in view (at most 2,000 of them, evenly taken, as queries; every return as a
/// candidate) whose nearest other return in (azimuth, elevation) is within 20 deg of horizontal.
/// A scanning LiDAR's returns come in rings, so their nearest neighbours lie along the image rows
/// (measured 0.51-0.99 on VoD, KITTI-class, Astyx VLP-16, nuScenes and 16/32/64-beam synthetic
/// scans, 1 in 4 returns); scattered returns give ~0.2 (40 of 180 deg; radar measured 0.12-0.31).
/// 0 with fewer than two returns.
double scanLineShare(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles);

/// Sets the given plane from a camera-to-world pose whose world z points up (a VoD pose, tf from
/// odom or map): `up` always, the camera height only when the pose's z is a plausible height above
/// the road (0.2-5 m); a map frame whose z = 0 is not the road keeps the parameters' height.
/// plane_source becomes kPose.
void applyCameraPose(const Eigen::Matrix4d& camera_to_world, GroundPriorParams& params);

const char* toString(GroundPriorParams::PlaneSource source);

}  // namespace multimodal_nvs
