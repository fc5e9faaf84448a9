#pragma once
// The conditioning renderer's side of the ROS boundary: the depth nodelet's outputs plus the camera
// image -> the keyframe the core lifts into a coloured cloud, rendered frames -> Image and
// CameraInfo, and the one mapping between cfg/ConditioningRenderer.cfg and the core's parameters.
// Everything that comes in is checked here; a failure is a typed RendererFault with a sentence
// naming the topic and values, so the nodelet counts and drops instead of catching exceptions.
#include <multimodal_nvs/ConditioningRendererConfig.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>
#include <opencv2/core.hpp>
#include <string>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/render_burst.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"
#include "multimodal_nvs/ros/conversions.hpp"

namespace multimodal_nvs {

// ---- Parameters
// ----------------------------------------------------------------------------------

enum class TrajectorySource { kTf, kPreset };

/// Everything one frame or one burst needs besides its messages; the nodelet copies it per frame.
struct ConditioningRendererSettings {
  TrajectorySource source = TrajectorySource::kTf;
  std::string world_frame = "odom";
  /// Seconds of header time between automatic keyframes; 0: only the first frame and ~set_keyframe.
  double keyframe_interval = 0.0;
  SplatParams splat;
  /// As the tool's --resize-depth. backprojection.resize_to_render holds the choice for a depth
  /// grid at least as large as the render size; keyframeBackprojection() resolves it for the actual
  /// grid.
  DepthResize resize_depth = DepthResize::kAuto;
  /// Holds the render size (backprojection.render_size) with the depth preparation.
  BackprojectionParams backprojection;
  TrajectoryPreset preset = TrajectoryPreset::kForward;
  double magnitude = 1.0;
  int num_frames = 121;
  double burst_frame_rate = 24.0;
  std::string export_dir;  ///< empty: no GEN3C export
  int threads = 0;         ///< 0: all cores

  ImageSize renderSize() const { return backprojection.render_size; }
};

/// Config -> settings. Throws InputError naming the bad parameter (unknown splat mode, preset,
/// trajectory source or resize choice, non-positive render size or frame count).
ConditioningRendererSettings rendererSettingsFromConfig(const ConditioningRendererConfig& config);

/// Settings -> config (the way back, used to restore the last valid values after a bad update).
void writeRendererSettingsToConfig(const ConditioningRendererSettings& settings,
                                   ConditioningRendererConfig& config);

/// The depth preparation for a keyframe whose depth grid is `grid`: resize_to_render by the core's
/// rule for a known grid (resizesDepthToRender in core/render/render_burst.hpp).
BackprojectionParams keyframeBackprojection(const ConditioningRendererSettings& settings,
                                            const ImageSize& grid);

namespace ros_conversions {

// ---- Input faults
// --------------------------------------------------------------------------------

/// Why an input set was rejected by the renderer. The image and CameraInfo faults carry the same
/// names as the depth nodelet's InputFault (they come from the same checks).
enum class RendererFault {
  kNone = 0,
  kImageEncoding,         ///< image not rgb8, bgr8, rgba8, bgra8 or mono8
  kImageStep,             ///< image step or data too short
  kImageEmpty,            ///< image width or height 0
  kDepthImage,            ///< depth/image not 32FC1 / 16UC1, empty, or step/data too short
  kMaskImage,             ///< depth/mask not mono8 / 8UC1, or step/data too short
  kMaskSize,              ///< depth/mask size differs from depth/image's
  kGridSize,              ///< depth grid neither the image size nor a stride grid of it
  kCameraInfoIntrinsics,  ///< depth/camera_info K not a valid pinhole matrix (e.g. all zero)
  kCameraInfoSize,        ///< depth/camera_info size differs from depth/image's
  kTransformUnavailable,  ///< no tf from world_frame to the camera frame at the image stamp
  kNoKeptPixel,           ///< a keyframe candidate with no kept pixel of positive depth
};
constexpr int kRendererFaultCount = static_cast<int>(RendererFault::kNoKeptPixel) + 1;

/// Short snake_case name, used as the diagnostics key ("rejected <name>").
const char* toString(RendererFault fault);

struct RendererStatus {
  RendererFault fault = RendererFault::kNone;
  std::string reason;

  bool ok() const { return fault == RendererFault::kNone; }
  static RendererStatus success() { return {}; }
  static RendererStatus failure(RendererFault fault, std::string reason) {
    return {fault, std::move(reason)};
  }
};

/// The depth nodelet's image/CameraInfo/tf faults under the renderer's names; `topic` prefixes
/// the reason.
RendererStatus fromConversion(const ConversionStatus& status, const std::string& topic);

// ---- Inputs
// --------------------------------------------------------------------------------------

/// One synchronized set (image, depth/image, depth/mask, depth/camera_info) checked and, when asked
/// for, converted to what the core lifts. The depth may sit on a stride grid of the image (the
/// depth nodelet's `stride`): grid pixel (r, c) is image pixel (c s, r s) and depth/camera_info
/// holds K / s.
struct RendererInput {
  std_msgs::Header header;  ///< the image's
  ImageSize image_size;
  ImageSize grid_size;
  int stride = 1;
  PinholeIntrinsics grid_intrinsics;   ///< from depth/camera_info
  PinholeIntrinsics image_intrinsics;  ///< at the image size: grid K times the stride

  // Filled only when converting pixels (a keyframe):
  cv::Mat image_bgr;  ///< CV_8UC3, image size (the GEN3C export's input image)
  cv::Mat grid_bgr;   ///< CV_8UC3, the image sampled at the grid pixels
  cv::Mat depth;      ///< CV_32FC1 metres on the grid, 0 where there is no depth
  cv::Mat kept;       ///< CV_8UC1 on the grid, nonzero = kept by the depth nodelet
};

/// Checks encodings, steps and sizes of the four messages and that the depth grid is a stride grid
/// of the image; with `convert_pixels` also copies the pixels into `out` (otherwise they are never
/// read). 32FC1 depth is metres with NaN/Inf/<= 0 = none (REP 118); 16UC1 is millimetres, 0 = none.
RendererStatus rendererInputFromMessages(const sensor_msgs::Image& image,
                                         const sensor_msgs::Image& depth,
                                         const sensor_msgs::Image& mask,
                                         const sensor_msgs::CameraInfo& depth_info,
                                         bool convert_pixels, RendererInput& out);

/// The stride of strideGridOfSize(image, grid) (core/common/stride_grid.hpp); kGridSize naming
/// both sizes when no stride fits.
RendererStatus gridStride(const ImageSize& image, const ImageSize& grid, int& stride);

// ---- Outputs
// -------------------------------------------------------------------------------------

/// CV_8UC3 BGR -> rgb8.
sensor_msgs::ImagePtr rgbImageFromBgr(const cv::Mat& bgr, const std_msgs::Header& header);
/// CV_8UC1 -> mono8 (the rendered hole mask: 255 covered, 0 hole).
sensor_msgs::ImagePtr monoImage(const cv::Mat& mono, const std_msgs::Header& header);
/// Rendered target-camera depth (CV_32FC1) -> 32FC1 metres with NaN in holes (REP 118).
sensor_msgs::ImagePtr renderedDepthImage(const cv::Mat& depth, const cv::Mat& mask,
                                         const std_msgs::Header& header);
/// Ideal pinhole camera of a rendered frame: K and P = [K | 0] at the render size, no distortion.
sensor_msgs::CameraInfoPtr renderedCameraInfo(const PinholeIntrinsics& intrinsics,
                                              const ImageSize& size,
                                              const std_msgs::Header& header);

}  // namespace ros_conversions
}  // namespace multimodal_nvs
