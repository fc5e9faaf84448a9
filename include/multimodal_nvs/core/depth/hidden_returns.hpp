#pragma once
// LiDAR returns the camera cannot see. A LiDAR mounted above (or beside) the camera sees past the
// top of a near object to the surface behind it; projected into the image, those farther returns
// land on the near object, between its own scan lines, and an interpolation of the scan spreads
// the far depth over the object ("bleeding" of projected LiDAR through foreground objects, the
// reason the KITTI depth-completion benchmark filtered its ground truth; Uhrig et al., "Sparsity
// Invariant CNNs", 3DV 2017).
#include <Eigen/Core>
#include <vector>

#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// The usable samples without those hidden from the camera. A sample near the image is hidden
/// when, in its image column, the nearest nearer returns above and below it (the neighbouring scan
/// lines, within two typical scan-line spacings) are of one surface (depths within `depth_ratio`)
/// and the scanner, at `scan_origin` (camera frame, metres), saw the sample above or below that
/// pair: its ray passed beside the surface that the camera's ray meets. A sample between the bars
/// of a railing or the leaves of a tree lies between them from both viewpoints and is kept, as is a
/// return beside or above a near object (a near return on one side only). The column is two
/// along-line spacings wide; both spacings are the samples' own (median nearest-neighbour distance,
/// median gap to the next sample above), so no beam count is assumed. Samples far from the image
/// pass through; the kept samples keep the input's order.
/// `dropped` (optional): how many were left out.
std::vector<AngularSample> dropReturnsHiddenFromCamera(const std::vector<AngularSample>& samples,
                                                       const PixelAngleGrid& angles,
                                                       double depth_ratio,
                                                       const Eigen::Vector3d& scan_origin,
                                                       std::size_t* dropped = nullptr);

/// Records where the scan was taken (the sensor-to-camera transform's translation) for the dense
/// mode's filter (GroundPriorParams::drop_hidden_returns).
inline void setScanOrigin(const Eigen::Vector3d& origin_in_camera, GroundPriorParams& ground) {
  ground.scan_origin_known = true;
  ground.scan_origin_x = origin_in_camera.x();
  ground.scan_origin_y = origin_in_camera.y();
  ground.scan_origin_z = origin_in_camera.z();
}

}  // namespace multimodal_nvs
