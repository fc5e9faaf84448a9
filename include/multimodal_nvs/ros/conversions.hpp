#pragma once
// ROS messages <-> core types. Everything that comes in is validated here, before the core sees
// it, and a failure comes back as a typed InputFault with a specific reason: callbacks drop the
// message and count the fault instead of catching exceptions. No algorithm lives here.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <Eigen/Geometry>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

/// Why an input message was rejected. Diagnostics count rejections per fault.
enum class InputFault {
  kNone = 0,
  // PointCloud2
  kCloudMissingField,   ///< no x, y or z field
  kCloudFieldDatatype,  ///< x/y/z not FLOAT32 or FLOAT64
  kCloudFieldCount,     ///< x/y/z field with count != 1
  kCloudFieldOffset,    ///< field offset + size > point_step
  kCloudLayout,         ///< point_step 0, width * point_step > row_step, or size overflow
  kCloudDataTooShort,   ///< data.size() < row_step * height
  kCloudBigEndian,      ///< byte order differs from the host's
  kCloudEmpty,          ///< width * height == 0
  kCloudNoFinitePoint,  ///< every point has a NaN or Inf coordinate
  kCloudBehindCamera,   ///< no finite point has a positive depth in the camera frame
  // Image / CompressedImage
  kImageEncoding,  ///< not rgb8, bgr8, rgba8, bgra8 or mono8
  kImageStep,      ///< step < width * channels, or data shorter than step * height
  kImageEmpty,     ///< width or height is 0
  kImageDecode,    ///< compressed payload is not a decodable jpeg/png
  // CameraInfo
  kCameraInfoIntrinsics,  ///< K not a valid pinhole matrix (e.g. all zero)
  kCameraInfoSize,        ///< CameraInfo width/height differ from the image's
  kCameraInfoDistortion,  ///< distortion_model unsupported (e.g. equidistant) or D malformed
  // Pairing
  kTransformUnavailable,  ///< no tf from the cloud frame to the image frame at the cloud stamp
  kStampNotNewer,         ///< image stamp equal to (duplicate) or just before the last set's
  // Resources
  kOutOfMemory,  ///< the model could not allocate its buffers for this set
};
constexpr int kInputFaultCount = static_cast<int>(InputFault::kOutOfMemory) + 1;

/// Short snake_case name of the fault, used as the diagnostics key.
const char* toString(InputFault fault);

/// Outcome of a conversion: ok, or a fault and a sentence naming the field and values involved.
struct ConversionStatus {
  InputFault fault = InputFault::kNone;
  std::string reason;

  bool ok() const { return fault == InputFault::kNone; }
  static ConversionStatus success() { return {}; }
  static ConversionStatus failure(InputFault fault, std::string reason) {
    return {fault, std::move(reason)};
  }
};

// ---- Inputs
// --------------------------------------------------------------------------------------

/// Reads x, y, z (FLOAT32 or FLOAT64, any offsets, any extra fields, organised or not) and applies
/// `sensor_to_camera` in double precision. Non-finite points are skipped and counted in
/// `non_finite` (organised LiDAR clouds mark missing returns with NaN); a cloud whose points are
/// all non-finite is rejected. `points` is cleared first.
ConversionStatus pointsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                 const Eigen::Isometry3d& sensor_to_camera,
                                 std::vector<Eigen::Vector3d>& points, std::size_t* non_finite);
/// Same without a transform, in float (for tools and tests).
ConversionStatus pointsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                 std::vector<Eigen::Vector3f>& points);

/// The same, reading at most about `max_points` records: with more, every k-th record (k =
/// ceil(width * height / max_points)) so that a huge cloud costs neither the memory of all its
/// points nor the model's time on them. `subsampled` (optional) receives k. 0: every record.
ConversionStatus pointsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                 const Eigen::Isometry3d& sensor_to_camera, std::size_t max_points,
                                 std::vector<Eigen::Vector3d>& points, std::size_t* non_finite,
                                 std::size_t* subsampled);

/// kCloudBehindCamera unless a point (camera frame) has z > 0: without one no pixel has a depth.
ConversionStatus checkPointsInFront(const std::vector<Eigen::Vector3d>& points_camera);

/// Checks everything `pointsFromCloud` checks about the layout without reading a point.
ConversionStatus validateCloudLayout(const sensor_msgs::PointCloud2& cloud);

/// Checks encoding, size and step of an image without touching its pixels.
ConversionStatus validateImage(const sensor_msgs::Image& image);

/// The channel order of a CV_8UC3 image: ROS messages and the renderer's colours are usually RGB,
/// the core's depth models take OpenCV's BGR (what cv::imread gives the tools).
enum class ChannelOrder { kRgb, kBgr };

/// Image -> CV_8UC3 view in `order`. An encoding already in that order (rgb8 for kRgb, bgr8 for
/// kBgr) is wrapped without a copy (the Mat points into `image.data`, which must outlive it);
/// other encodings are converted into a new buffer. Honours `step`.
ConversionStatus colourFromImage(const sensor_msgs::Image& image, ChannelOrder order, cv::Mat& out);

/// Decodes a jpeg or png CompressedImage into BGR (CV_8UC3), OpenCV's order.
ConversionStatus bgrFromCompressed(const sensor_msgs::CompressedImage& image, cv::Mat& bgr);

/// The image of a synchronized set as depth completion needs it: header and size at once, the
/// pixels on demand: RGB for the coloured cloud (depth/points), BGR for the models that read the
/// image (the core's order).
struct FrameImage {
  std_msgs::Header header;
  ImageSize size;
  std::function<ConversionStatus(cv::Mat&)> rgb;
  std::function<ConversionStatus(cv::Mat&)> bgr;
};

/// Raw image: validated without touching its pixels; `rgb` / `bgr` are colourFromImage (an
/// encoding in that order wrapped without a copy), so `image` must outlive `frame`.
ConversionStatus frameImage(const sensor_msgs::Image& image, FrameImage& frame);
/// Compressed image: decoded at once, since decoding is the only way to learn its size.
ConversionStatus frameImage(const sensor_msgs::CompressedImage& image, FrameImage& frame);

/// CameraInfo -> intrinsics from K; the CameraInfo's size must equal `image_size`.
ConversionStatus intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info,
                                          const ImageSize& image_size,
                                          PinholeIntrinsics& intrinsics);

// ---- Outputs
// -------------------------------------------------------------------------------------

// The images are written into a message the caller owns, so that a node can recycle its previous
// output (RecycledMessage): a buffer of the right size is reused as it is.

/// Depth 32FC1 in metres on the stride grid, NaN where the pixel is not kept (REP 118).
void depthImage(const DepthMap& depth, const std_msgs::Header& header, sensor_msgs::Image& image);
/// Variance 32FC1 in m^2 for every grid pixel (+inf where the model made no prediction).
void varianceImage(const DepthMap& depth, const std_msgs::Header& header,
                   sensor_msgs::Image& image);
/// Kept mask mono8: 255 kept, 0 not.
void maskImage(const DepthMap& depth, const std_msgs::Header& header, sensor_msgs::Image& image);

/// CameraInfo describing the stride grid: the grid pixel (r, c) is the full-image pixel
/// (c * s, r * s), so K and P divide by s (no half-pixel shift, as the grid has none).
sensor_msgs::CameraInfoPtr gridCameraInfo(const sensor_msgs::CameraInfo& full,
                                          const StrideGrid& grid);

/// Unorganised cloud of float32 records, one field a name in that order (e.g. x, y, z, intensity);
/// `values` holds the records back to back. is_dense when every value is finite.
sensor_msgs::PointCloud2 float32Cloud(const std::vector<std::string>& names,
                                      const std::vector<float>& values,
                                      const std_msgs::Header& header);

/// XYZRGB cloud with uncertainty (float32 x, y, z, packed rgb, stddev in metres = sqrt(variance))
/// in the camera frame of the kept pixels, every `cloud_stride`-th grid pixel in each direction:
/// P = z K^-1 [u, v, 1] at the full-image pixel, colour = `rgb` (full-image CV_8UC3) at that
/// pixel. Unorganised, dense. Written into `cloud`,
/// whose buffer is reused when it is large enough. With `pool`, rows are written in parallel (the
/// same bytes as without).
void coloredCloud(const DepthMap& depth, const PinholeIntrinsics& intrinsics, const cv::Mat& rgb,
                  int cloud_stride, const std_msgs::Header& header, sensor_msgs::PointCloud2& cloud,
                  ThreadPool* pool = nullptr);

}  // namespace ros_conversions
}  // namespace multimodal_nvs
