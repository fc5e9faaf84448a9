#include "multimodal_nvs/ros/depth_frame.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <new>
#include <string>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/depth/hidden_returns.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

ConversionStatus lookupSensorToCamera(const tf2_ros::Buffer& tf_buffer,
                                      const std_msgs::Header& cloud_header,
                                      const std_msgs::Header& camera_header,
                                      const CloudToCamera& how,
                                      Eigen::Isometry3d& sensor_to_camera) {
  const bool across_time = !how.fixed_frame.empty() && cloud_header.stamp != camera_header.stamp;
  if (cloud_header.frame_id == camera_header.frame_id && !across_time) {
    sensor_to_camera.setIdentity();
    return ConversionStatus::success();
  }
  try {
    sensor_to_camera = tf2::transformToEigen(
        across_time ? tf_buffer.lookupTransform(camera_header.frame_id, camera_header.stamp,
                                                cloud_header.frame_id, cloud_header.stamp,
                                                how.fixed_frame, how.timeout)
                    : tf_buffer.lookupTransform(camera_header.frame_id, cloud_header.frame_id,
                                                cloud_header.stamp, how.timeout));
    return ConversionStatus::success();
  } catch (const tf2::TransformException& e) {
    return ConversionStatus::failure(InputFault::kTransformUnavailable, e.what());
  }
}

ConversionStatus lookupGroundPlane(const tf2_ros::Buffer& tf_buffer,
                                   const std_msgs::Header& camera_header, const GroundFromTf& how,
                                   GroundPriorParams& ground) {
  if (how.frame.empty()) return ConversionStatus::success();
  try {
    const Eigen::Isometry3d camera_to_ground = tf2::transformToEigen(tf_buffer.lookupTransform(
        how.frame, camera_header.frame_id, camera_header.stamp, how.timeout));
    applyCameraPose(camera_to_ground.matrix(), ground);
    return ConversionStatus::success();
  } catch (const tf2::TransformException& e) {
    return ConversionStatus::failure(InputFault::kTransformUnavailable,
                                     "ground_frame '" + how.frame + "': " + e.what());
  }
}

ConversionStatus completeDepthFromCloud(const sensor_msgs::PointCloud2& cloud,
                                        const Eigen::Isometry3d& sensor_to_camera,
                                        const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                                        const DepthCompletionParams& params, int max_points,
                                        DepthCompletionWorkspace& workspace, CloudReading& reading,
                                        const cv::Mat& image) {
  reading = CloudReading{};
  reading.cap = pointCap(max_points, params);
  std::size_t step = 1;
  ConversionStatus status = pointsFromCloud(cloud, sensor_to_camera, reading.cap,
                                            workspace.points(), &reading.non_finite, &step);
  if (!status.ok()) return status;
  status = checkPointsInFront(workspace.points());
  if (!status.ok()) return status;
  reading.step = step;  // only for a cloud that goes on to the model
  const std::size_t points = workspace.points().size();  // the workspace may release them
  // The scan's origin in the camera frame, for the dense mode's hidden-return filter.
  DepthCompletionParams scan_params = params;
  setScanOrigin(sensor_to_camera.translation(), scan_params.ground);
  try {
    workspace.complete(intrinsics, grid, scan_params, image);
  } catch (const std::bad_alloc&) {
    // One allocation too large for this host (the model's buffers grow with points and pixels):
    // the set is lost, the node is not. The thread pool rethrows its workers' exceptions here.
    return ConversionStatus::failure(InputFault::kOutOfMemory,
                                     "depth completion of " + std::to_string(points) +
                                         " points on a " + std::to_string(grid.image.width) + "x" +
                                         std::to_string(grid.image.height) +
                                         " image ran out of memory");
  }
  return ConversionStatus::success();
}

DepthFrameResult completeDepthFrame(const sensor_msgs::PointCloud2& cloud, const FrameImage& image,
                                    const sensor_msgs::CameraInfo& info,
                                    const tf2_ros::Buffer& tf_buffer,
                                    const CloudToCamera& cloud_to_camera,
                                    const GroundFromTf& ground_from_tf,
                                    const DepthCompletionSettings& settings, int max_points,
                                    DepthCompletionWorkspace& workspace) {
  DepthFrameResult result;
  result.input = "camera_info";
  result.status = intrinsicsFromCameraInfo(info, image.size, result.intrinsics);
  if (!result.status.ok()) return result;
  result.input = "points";
  result.status = validateCloudLayout(cloud);
  if (!result.status.ok()) return result;
  Eigen::Isometry3d sensor_to_camera;
  result.input = "tf";
  result.status = lookupSensorToCamera(tf_buffer, cloud.header, image.header, cloud_to_camera,
                                       sensor_to_camera);
  if (!result.status.ok()) return result;
  // The ground plane from tf, for the models that have one (a copy of the parameters only then).
  DepthCompletionParams with_ground;
  const DepthCompletionParams* params = &settings.params;
  if (!ground_from_tf.frame.empty() && settings.params.usesGroundPlane()) {
    with_ground = settings.params;
    result.status = lookupGroundPlane(tf_buffer, image.header, ground_from_tf, with_ground.ground);
    if (!result.status.ok()) return result;
    params = &with_ground;
  }
  // Only image_guided and ground_gp's sky and colours read the pixels, in the core's BGR order
  // like cv::imread's (the sky's colour test and brightness read the channels by position); a
  // compressed image is already decoded, a bgr8 one wrapped.
  cv::Mat pixels;
  if (settings.params.readsImage()) {
    result.input = "image";
    result.status = image.bgr(pixels);
    if (!result.status.ok()) return result;
  }
  result.input = "points";
  try {
    result.status = completeDepthFromCloud(cloud, sensor_to_camera, result.intrinsics,
                                           StrideGrid{image.size, settings.stride}, *params,
                                           max_points, workspace, result.reading, pixels);
  } catch (const InputError& e) {
    result.error = e.what();
  }
  return result;
}

}  // namespace ros_conversions
}  // namespace multimodal_nvs
