#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Eigenvalues>

#include "multimodal_nvs/core/depth/angular_bins.hpp"
#include "multimodal_nvs/core/depth/models/ground_gp_model.hpp"

namespace multimodal_nvs {
namespace {
// Returns farther than this are left out of the fit: the road bends and slopes with distance, and
// a far return's elevation error is metres.
constexpr double kMaxRangeM = 40.0;
// The ground's normal within this angle of the expected up (pose, tf or parameters): a wall or a
// vehicle's side is never taken for the ground, a slope of up to ~35 % is.
constexpr double kMaxTiltDeg = 20.0;
// Fewer returns than this in view give no fit (and no verdict on their precision).
constexpr std::size_t kMinReturns = 30;
// A fit is LiDAR-precise only with at least this many returns on it, besides precise_fraction of
// them: among a few dozen scattered returns, RANSAC's best of 200 planes holds a quarter of them by
// chance. Measured (plane_distance 0.1 m): the synthetic radar fits at fractions >= 0.25 held
// 14-54 returns and were wrong (dev_s11, dev_s41: planes 1.1-1.2 m above the road, 5-7 deg tilted,
// taken over the pose), every radar fit 14-90 (VoD, Astyx; synthetic); LiDAR, 1 in 4 returns,
// at least 129 (Astyx VLP-16; nuScenes 435, KITTI 1,688, synthetic 16-64 beams 188), within 3 deg.
constexpr std::size_t kMinPreciseInliers = 80;
// A 2D scanner (nuScenes' radar: 1.2 deg of elevation spread) has every return on its own scan
// plane; scanning LiDAR and 3D radar spread over 2.7-8 deg (measured on VoD, Astyx, nuScenes).
constexpr double kMinElevationSpreadDeg = 2.0;
// A 2D scanner reports its returns on its scan plane (no elevation measured: nuScenes' radar, z = 0
// in its frame), so all of them lie within centimetres of one plane, at any range; a 3D radar's or
// a LiDAR's returns spread metres off any plane (measured: VoD radar 2.3-3.5 m RMS, Astyx 2.4-2.9,
// nuScenes radar 0.000). The verdict needs a dozen returns in view.
constexpr double kScanPlaneRmsM = 0.05;
constexpr std::size_t kMinScanPlaneReturns = 12;
// A camera on a vehicle or a robot sits this high above the road.
constexpr double kMinHeightM = 0.2, kMaxHeightM = 5.0;
// Returns more than this below the plane contradict it (nothing is seen through the road); at most
// this share of them is tolerated (noise, multipath).
constexpr double kBelowM = 0.5, kMaxBelowFraction = 0.05;
// RANSAC budget: returns used for the fit (every k-th beyond this) and iterations; the inliers are
// then counted on every return.
constexpr std::size_t kMaxFitPoints = 4000;
constexpr int kMaxIterations = 200;
// Scan lines: a nearest neighbour within this angle of horizontal counts as along a row; the share
// that makes returns LiDAR rings (scattered returns: ~0.22, radar measured at most 0.31, LiDAR at
// least 0.51); the ground share they need besides (a 2D scanner's single line has no ground
// returns; LiDAR measured at least 0.19).
constexpr double kScanLineSlopeDeg = 20.0;
constexpr double kScanLineShare = 0.4;
constexpr double kScanLineGroundFraction = 0.1;
constexpr std::size_t kMaxScanLineQueries = 2000;

struct InView {
  std::vector<Eigen::Vector3d> points;
  double elevation_spread_deg = 0.0;  // standard deviation
  // Every return in view (any range): how many, and the RMS distance of their points to the plane
  // that fits them best (least squares; +inf with fewer than three).
  std::size_t all_returns = 0;
  double plane_rms_m = INFINITY;
};

/// Tells a return with a positive finite depth whose direction projects inside the image. Those
/// outside the image's azimuths are told before any tangent (azimuthWindow): most of a 360-degree
/// LiDAR sweep.
class ReturnInImage {
 public:
  explicit ReturnInImage(const PixelAngleGrid& angles)
      : angles_(angles),
        window_(azimuthWindow(angles.intrinsics(), 0.0, angles.grid().image.width - 1.0)) {}
  bool operator()(const AngularSample& s) const {
    if (!(s.depth > 0.0f) || !std::isfinite(s.depth) || !window_.contains(s.azimuth_deg)) {
      return false;
    }
    const ImageSize& image = angles_.grid().image;
    double u = 0.0, v = 0.0;
    if (!angularToPixel(angles_.intrinsics(), s.azimuth_deg, s.elevation_deg, &u, &v)) {
      return false;
    }
    return !(u < 0.0 || v < 0.0 || u > image.width - 1 || v > image.height - 1);
  }

 private:
  const PixelAngleGrid& angles_;
  AzimuthWindow window_;
};

InView returnsInView(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles) {
  InView v;
  double sum = 0.0, sum2 = 0.0;
  const ReturnInImage in_image(angles);
  Eigen::Vector3d moment1 = Eigen::Vector3d::Zero();
  Eigen::Matrix3d moment2 = Eigen::Matrix3d::Zero();
  for (const AngularSample& s : samples) {
    if (!in_image(s)) continue;
    const Eigen::Vector2d ray = normalisedFromAngles(s.azimuth_deg, s.elevation_deg);
    const Eigen::Vector3d p(ray.x() * s.depth, ray.y() * s.depth, s.depth);
    ++v.all_returns;
    moment1 += p;
    moment2 += p * p.transpose();
    if (p.norm() > kMaxRangeM) continue;
    v.points.push_back(p);
    sum += s.elevation_deg;
    sum2 += double(s.elevation_deg) * s.elevation_deg;
  }
  const double n = static_cast<double>(v.points.size());
  if (n > 0) v.elevation_spread_deg = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  if (v.all_returns >= 3) {
    const double all = static_cast<double>(v.all_returns);
    const Eigen::Vector3d mean = moment1 / all;
    const Eigen::Matrix3d covariance = moment2 / all - mean * mean.transpose();
    const double smallest =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly)
            .eigenvalues()(0);
    v.plane_rms_m = std::sqrt(std::max(0.0, smallest));
  }
  return v;
}
// A plane n . X + offset = 0, |n| = 1, n on the camera's side (towards `up`): the camera (X = 0)
// is `offset` above it.
struct RansacPlane {
  Eigen::Vector3d normal{0.0, -1.0, 0.0};
  double offset = 0.0;
  std::size_t inliers = 0;
};

// RANSAC (Fischler and Bolles 1981) for the plane with the most returns within `distance`, among
// the planes whose normal is within kMaxTiltDeg of `up`. Written here rather than taken from PCL's
// sample_consensus: Debian's PCL is built for generic x86-64 (Eigen's 16-byte alignment and
// malloc) while this package compiles with -march=native (64-byte alignment on AVX-512), and
// mixing the two crashed in Eigen's aligned free on the first call (measured). Deterministic: a
// fixed-seed generator, so a scan always gives the same plane.
RansacPlane ransacPlane(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                        double distance) {
  RansacPlane best;
  const std::size_t n = points.size();
  if (n < 3) return best;
  const double min_cos = std::cos(kMaxTiltDeg * M_PI / 180.0);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // splitmix64
  auto next = [&state, n]() {
    state += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<std::size_t>((z ^ (z >> 31)) % n);
  };
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const Eigen::Vector3d& a = points[next()];
    const Eigen::Vector3d& b = points[next()];
    const Eigen::Vector3d& c = points[next()];
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const double length = normal.norm();
    if (!(length > 1e-9)) continue;
    normal /= length;
    if (normal.dot(up) < 0.0) normal = -normal;
    if (normal.dot(up) < min_cos) continue;
    const double offset = -normal.dot(a);
    std::size_t inliers = 0;
    for (const Eigen::Vector3d& p : points)
      inliers += std::abs(normal.dot(p) + offset) <= distance;
    if (inliers > best.inliers) best = {normal, offset, inliers};
  }
  return best;
}

// Least-squares plane (smallest principal axis) of the returns within `distance` of the plane,
// keeping the orientation towards the camera. Unchanged with fewer than 3 inliers.
void refineOnInliers(const std::vector<Eigen::Vector3d>& points, double distance,
                     Eigen::Vector3d& normal, double& offset) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  for (const Eigen::Vector3d& p : points) {
    if (std::abs(normal.dot(p) + offset) > distance) continue;
    mean += p;
    ++count;
  }
  if (count < 3) return;
  mean /= double(count);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    if (std::abs(normal.dot(p) + offset) > distance) continue;
    scatter += (p - mean) * (p - mean).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Eigen::Vector3d refined = solver.eigenvectors().col(0);  // smallest eigenvalue
  if (!refined.allFinite()) return;
  if (refined.dot(normal) < 0.0) refined = -refined;
  normal = refined.normalized();
  offset = -normal.dot(mean);
}
}  // namespace

double scanLineShare(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles) {
  std::vector<AngularSample> in_view;
  float az0 = INFINITY, az1 = -INFINITY, el0 = INFINITY, el1 = -INFINITY;
  const ReturnInImage in_image(angles);
  for (const AngularSample& s : samples) {
    if (!in_image(s)) continue;
    in_view.push_back(s);
    az0 = std::min(az0, s.azimuth_deg);
    az1 = std::max(az1, s.azimuth_deg);
    el0 = std::min(el0, s.elevation_deg);
    el1 = std::max(el1, s.elevation_deg);
  }
  if (in_view.size() < 2) return 0.0;
  // Bins holding a few returns each on average over the returns' extent.
  const double area = std::max(1e-6, double(az1 - az0) * double(el1 - el0));
  const AngularBins bins(in_view, std::max(0.01, std::sqrt(4.0 * area / double(in_view.size()))));
  const double slope = std::tan(kScanLineSlopeDeg * M_PI / 180.0);
  const std::size_t every = (in_view.size() + kMaxScanLineQueries - 1) / kMaxScanLineQueries;
  std::vector<std::pair<double, int>> nearest;
  std::size_t queries = 0, along_rows = 0;
  for (std::size_t q = 0; q < in_view.size(); q += every) {
    const AngularSample& query = in_view[q];
    bins.nearest(query.azimuth_deg, query.elevation_deg, 2, nearest);
    // The query itself is among its two nearest (at distance 0); the other one is its neighbour.
    const auto other =
        std::find_if(nearest.begin(), nearest.end(),
                     [q](const std::pair<double, int>& n) { return n.second != int(q); });
    if (other == nearest.end()) continue;
    const AngularSample& neighbour = in_view[std::size_t(other->second)];
    const double d_az = double(neighbour.azimuth_deg) - query.azimuth_deg;
    const double d_el = double(neighbour.elevation_deg) - query.elevation_deg;
    ++queries;
    along_rows += std::abs(d_el) <= slope * std::abs(d_az);
  }
  return queries == 0 ? 0.0 : double(along_rows) / double(queries);
}

GroundPlane givenGroundPlane(const GroundPriorParams& g) {
  GroundPlane plane;
  plane.up = Eigen::Vector3d(g.up_x, g.up_y, g.up_z).normalized();
  plane.height = g.camera_height;
  return plane;
}

GroundPlaneFit estimateGroundPlane(const std::vector<AngularSample>& samples,
                                   const PixelAngleGrid& angles, const GroundPlane& expected,
                                   const GroundPriorParams& params) {
  GroundPlaneFit fit;
  const InView view = returnsInView(samples, angles);
  fit.returns = view.points.size();
  fit.single_scan_plane =
      view.all_returns >= kMinScanPlaneReturns && view.plane_rms_m < kScanPlaneRmsM;
  if (fit.returns < kMinReturns || view.elevation_spread_deg < kMinElevationSpreadDeg) return fit;

  const std::size_t every = (fit.returns + kMaxFitPoints - 1) / kMaxFitPoints;
  std::vector<Eigen::Vector3d> fit_points;
  for (std::size_t i = 0; i < fit.returns; i += every)
    fit_points.push_back(view.points[i]);
  const RansacPlane best = ransacPlane(fit_points, expected.up, params.plane_distance);
  if (best.inliers == 0) return fit;
  Eigen::Vector3d normal = best.normal;
  double d = best.offset;
  refineOnInliers(view.points, params.plane_distance, normal, d);
  std::size_t below = 0;
  for (const Eigen::Vector3d& p : view.points) {
    const double signed_distance = normal.dot(p) + d;
    fit.inliers += std::abs(signed_distance) <= params.plane_distance;
    below += signed_distance < -kBelowM;
  }
  fit.inlier_fraction = double(fit.inliers) / double(fit.returns);
  fit.plane.up = normal;
  fit.plane.height = d;
  fit.found = d >= kMinHeightM && d <= kMaxHeightM &&
              double(below) <= kMaxBelowFraction * double(fit.returns);
  return fit;
}

GroundChoice chooseGround(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                          const DepthCompletionParams& params) {
  using Input = GroundPriorParams::Input;
  const GroundPriorParams& g = params.ground;
  GroundChoice choice;
  choice.plane = givenGroundPlane(g);
  choice.source = g.plane_source;
  // The fit serves the plane (estimate_plane) and the auto mode; skip it when neither needs it.
  GroundPlaneFit fit;
  const bool fit_needed = g.estimate_plane || g.input == Input::kAuto;
  if (fit_needed) fit = estimateGroundPlane(samples, angles, choice.plane, g);
  const bool judged = fit.returns >= kMinReturns && fit.inliers > 0;
  const bool precise =
      judged && fit.inliers >= kMinPreciseInliers && fit.inlier_fraction >= g.precise_fraction;
  choice.inlier_fraction = fit.inlier_fraction;
  choice.plane_fitted = fit.found;
  choice.single_scan_plane = fit.single_scan_plane;
  if (g.estimate_plane && fit.found && precise) {
    choice.plane = fit.plane;
    choice.source = GroundPriorParams::PlaneSource::kReturns;
  }
  if (g.input != Input::kAuto) {
    choice.dense = g.input == Input::kDense;
  } else if (precise && meanSampleSpacingDeg(samples, angles) <= params.radius_deg) {
    // LiDAR-precise and dense. A precise ground fit alone does not make a LiDAR: a radar mounted
    // high sees much road, and synthetic radar scans of 49-200 returns held 25-32 % of them on the
    // plane, which sent 4 of the 14 scenes to the dense mode (triangles between returns degrees
    // apart; on real radar that mode's MAE is 3-4x the sparse one's). Precise but sparse returns
    // take the scan-line test below (1 in 4 rings of nuScenes' 32-beam scan: rings 5.4 deg apart,
    // mean spacing above the radius, on scan lines).
    choice.dense = true;
  } else if (judged) {
    // Rings of a LiDAR whose scan holds few road returns (a tall or pitched mount, traffic around):
    // the inlier fraction alone took them for radar (measured on synthetic 16- and 64-beam scans:
    // 0.19-0.23 on the road, MAE 3.4-6.3 m in the sparse mode against 2.4-2.9 m dense). A precise
    // fit already holds enough ground returns.
    choice.scan_line_share = scanLineShare(samples, angles);
    choice.dense = choice.scan_line_share >= kScanLineShare &&
                   (precise || fit.inlier_fraction >= kScanLineGroundFraction);
  } else {
    choice.dense = groundInputIsDense(samples, angles, params);
  }
  return choice;
}

void applyCameraPose(const Eigen::Matrix4d& camera_to_world, GroundPriorParams& params) {
  const GroundPlane plane = GroundPlane::fromCameraToWorld(camera_to_world);
  if (!plane.up.allFinite()) return;
  params.up_x = plane.up.x();
  params.up_y = plane.up.y();
  params.up_z = plane.up.z();
  if (plane.height >= kMinHeightM && plane.height <= kMaxHeightM) {
    params.camera_height = plane.height;
  }
  params.plane_source = GroundPriorParams::PlaneSource::kPose;
}

const char* toString(GroundPriorParams::PlaneSource source) {
  switch (source) {
    case GroundPriorParams::PlaneSource::kParameters:
      return "parameters";
    case GroundPriorParams::PlaneSource::kPose:
      return "pose";
    case GroundPriorParams::PlaneSource::kReturns:
      return "returns";
  }
  return "unknown";
}

}  // namespace multimodal_nvs
