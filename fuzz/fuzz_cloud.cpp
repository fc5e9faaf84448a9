// PointCloud2 -> core points (ros_conversions::pointsFromCloud, validateCloudLayout): header, field
// list and data all come from the input (layout in fuzz_input.hpp). Besides memory errors and UB,
// checks that the entry points agree and that every (sampled) point is accounted for.
#include <Eigen/Geometry>
#include <cmath>

#include "fuzz_input.hpp"
#include "multimodal_nvs/ros/conversions.hpp"

namespace rc = multimodal_nvs::ros_conversions;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sensor_msgs::PointCloud2 cloud = mmnvs_fuzz::cloudFromBytes(data, size);
  const rc::ConversionStatus layout = rc::validateCloudLayout(cloud);

  // A non-identity transform so that the double-precision path does real arithmetic.
  Eigen::Isometry3d sensor_to_camera = Eigen::Isometry3d::Identity();
  sensor_to_camera.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  sensor_to_camera.translation() = Eigen::Vector3d(0.5, -1.0, 2.0);
  std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero()};  // must be cleared
  std::size_t non_finite = 0;
  const rc::ConversionStatus status =
      rc::pointsFromCloud(cloud, sensor_to_camera, points, &non_finite);

  std::vector<Eigen::Vector3f> points_float;
  const rc::ConversionStatus status_float = rc::pointsFromCloud(cloud, points_float);
  MMNVS_FUZZ_CHECK(status.fault == status_float.fault);
  MMNVS_FUZZ_CHECK(!status.ok() || points.size() == points_float.size());

  if (!layout.ok()) {
    // The layout check and the conversion reject for the same reason.
    MMNVS_FUZZ_CHECK(status.fault == layout.fault);
    MMNVS_FUZZ_CHECK(!layout.reason.empty());
    MMNVS_FUZZ_CHECK(points.empty());
    return 0;
  }
  // A valid layout is only rejected when no point is finite.
  MMNVS_FUZZ_CHECK(status.ok() || status.fault == rc::InputFault::kCloudNoFinitePoint);
  const std::size_t total = std::size_t(cloud.width) * cloud.height;
  if (status.ok()) {
    MMNVS_FUZZ_CHECK(points.size() + non_finite == total);
    for (const auto& p : points) {
      // Finite float inputs stay finite; doubles near DBL_MAX may overflow in the transform.
      MMNVS_FUZZ_CHECK(!std::isnan(p.x()) && !std::isnan(p.y()) && !std::isnan(p.z()));
    }
  } else {
    MMNVS_FUZZ_CHECK(points.empty());
  }

  // Subsampled reading (huge clouds): every k-th record, k = ceil(total / max_points). The limit
  // comes from the input size so that the encoding of the cloud stays the same.
  const std::size_t max_points = size % 7;
  std::size_t step = 0, sampled_non_finite = 0;
  std::vector<Eigen::Vector3d> sampled;
  const rc::ConversionStatus sampled_status =
      rc::pointsFromCloud(cloud, sensor_to_camera, max_points, sampled, &sampled_non_finite, &step);
  MMNVS_FUZZ_CHECK(sampled_status.ok() || !sampled_status.reason.empty());
  if (sampled_status.ok()) {
    MMNVS_FUZZ_CHECK(step >= 1);
    MMNVS_FUZZ_CHECK(max_points == 0 || sampled.size() <= max_points);
    MMNVS_FUZZ_CHECK(sampled.size() + sampled_non_finite == (total + step - 1) / step);
  }
  return 0;
}
