#pragma once
// One synchronized set through depth completion: intrinsics, the cloud's layout and its transform
// into the camera frame checked, the cloud read into the workspace within the point cap and
// completed by the core; every way it can fail comes back as an InputFault naming its input.
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <Eigen/Geometry>
#include <cstddef>
#include <string>

#include "multimodal_nvs/core/depth/depth_completion_workspace.hpp"
#include "multimodal_nvs/ros/conversions.hpp"
#include "multimodal_nvs/ros/depth_completion_config.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

/// Where the ground plane of the models that use one (`ground_gp`, `image_guided`) comes from when
/// the returns do not show it (a LiDAR's do, and their own plane wins): with an empty frame, the
/// ground_camera_height / ground_pitch_deg parameters; with a frame whose z axis points up and
/// whose z = 0 is the road (REP 120's base_footprint, or odom where it starts on the road), the
/// camera's height above it and the up direction, from tf at the image's stamp. The parameters
/// then describe only a camera mounted like VoD's; tf describes the vehicle the node runs on.
struct GroundFromTf {
  std::string frame;
  ros::Duration timeout{0.1};  ///< the longest wait for the transform
};

/// Sets `ground`'s plane from tf (camera_header's frame in `how.frame` at its stamp) when
/// `how.frame` is set, through the core's applyCameraPose: up always, the height only when it is
/// 0.2-5 m (a frame whose z = 0 is not the road keeps the parameters' height); plane_source becomes
/// kPose. Unchanged with an empty frame; kTransformUnavailable, naming the frame, when tf has no
/// such transform.
ConversionStatus lookupGroundPlane(const tf2_ros::Buffer& tf_buffer,
                                   const std_msgs::Header& camera_header, const GroundFromTf& how,
                                   GroundPriorParams& ground);

/// How a cloud's points are taken into the camera frame.
struct CloudToCamera {
  ros::Duration timeout{0.1};  ///< the longest wait for a transform
  /// Empty: the transform at the cloud's stamp, as if the image had been taken then. A frame fixed
  /// in the world (odom, map): the points where the sensor saw them at the cloud's stamp, seen from
  /// where the camera was at the image's stamp (tf2's lookup across two times), so that the
  /// vehicle's motion between the two stamps does not shift the returns against the image.
  std::string fixed_frame;
};

/// The transform from the cloud's frame at its stamp to the camera's frame (`camera_header`'s) at
/// the cloud's stamp, or with a fixed frame at the image's stamp, waiting up to `how.timeout` for
/// it; identity without a lookup when the frames are the same and nothing moves them apart (no
/// fixed frame, or equal stamps).
ConversionStatus lookupSensorToCamera(const tf2_ros::Buffer& tf_buffer,
                                      const std_msgs::Header& cloud_header,
                                      const std_msgs::Header& camera_header,
                                      const CloudToCamera& how,
                                      Eigen::Isometry3d& sensor_to_camera);

/// How the cloud was read.
struct CloudReading {
  std::size_t cap = 0;  ///< most points the model was to get (0: no limit), see pointCap
  /// Every step-th point went to the model (> 1: the cloud exceeded the cap); 1 when the cloud was
  /// rejected before the model.
  std::size_t step = 1;
  std::size_t non_finite = 0;
};

/// Reads `cloud` (layout already validated) into `workspace` in the camera frame, at most about
/// pointCap(max_points, params) points, and completes it into workspace.depth(). Rejects a cloud
/// without a point in front of the camera; a scan this host has no memory for comes back as
/// kOutOfMemory (the node keeps running, max_points keeps a dense cloud's buffers small in the
/// first place). Throws InputError for invalid parameters or intrinsics.
ConversionStatus completeDepthFromCloud(const sensor_msgs::PointCloud2& cloud,
                                        const Eigen::Isometry3d& sensor_to_camera,
                                        const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                                        const DepthCompletionParams& params, int max_points,
                                        DepthCompletionWorkspace& workspace, CloudReading& reading,
                                        const cv::Mat& image = cv::Mat());

/// Outcome of completeDepthFrame.
struct DepthFrameResult {
  ConversionStatus status;
  const char* input = "";  ///< the input `status` is about when it is a failure: its topic or "tf"
  PinholeIntrinsics intrinsics;
  CloudReading reading;
  /// The core's InputError for parameters or intrinsics, which the node validated before: not an
  /// input fault, not expected. `status` is ok then, but there is no depth.
  std::string error;

  bool completed() const { return status.ok() && error.empty(); }
};

/// The whole frame in the order its faults are reported: camera_info's intrinsics for `image`, the
/// cloud's layout (so that a malformed cloud is reported as such, not as a missing transform), its
/// transform (lookupSensorToCamera), the ground plane from tf when the model uses one
/// (lookupGroundPlane), then completeDepthFromCloud into workspace.depth().
DepthFrameResult completeDepthFrame(const sensor_msgs::PointCloud2& cloud, const FrameImage& image,
                                    const sensor_msgs::CameraInfo& info,
                                    const tf2_ros::Buffer& tf_buffer,
                                    const CloudToCamera& cloud_to_camera,
                                    const GroundFromTf& ground_from_tf,
                                    const DepthCompletionSettings& settings, int max_points,
                                    DepthCompletionWorkspace& workspace);

}  // namespace ros_conversions
}  // namespace multimodal_nvs
