#include "multimodal_nvs/ros/renderer_conversions.hpp"

#include <sensor_msgs/image_encodings.h>
#include <boost/make_shared.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "message_helpers.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"

namespace multimodal_nvs {

using ros_conversions::detail::concat;

// ---- Parameters

ConditioningRendererSettings rendererSettingsFromConfig(const ConditioningRendererConfig& config) {
  ConditioningRendererSettings s;
  if (config.trajectory_source == "tf") {
    s.source = TrajectorySource::kTf;
  } else if (config.trajectory_source == "preset") {
    s.source = TrajectorySource::kPreset;
  } else {
    throw InputError("parameter trajectory_source: '" + config.trajectory_source +
                     "' is neither tf nor preset");
  }
  if (config.world_frame.empty()) throw InputError("parameter world_frame must not be empty");
  s.world_frame = config.world_frame;
  if (!(config.keyframe_interval >= 0.0) || !std::isfinite(config.keyframe_interval)) {
    throw InputError("parameter keyframe_interval must be >= 0 (0: only ~set_keyframe)");
  }
  s.keyframe_interval = config.keyframe_interval;
  s.preset = parseTrajectoryPreset(config.preset);
  if (!(config.magnitude >= 0.0) || !std::isfinite(config.magnitude)) {
    throw InputError("parameter magnitude must be finite and >= 0");
  }
  s.magnitude = config.magnitude;
  if (config.num_frames < 1) throw InputError("parameter num_frames must be >= 1");
  s.num_frames = config.num_frames;
  if (!(config.burst_frame_rate > 0.0)) throw InputError("parameter burst_frame_rate must be > 0");
  s.burst_frame_rate = config.burst_frame_rate;
  s.export_dir = config.export_dir;

  s.splat.mode = parseSplatMode(config.splat);
  if (config.render_height < 1 || config.render_width < 1) {
    throw InputError("parameters render_height and render_width must be positive");
  }
  const std::optional<DepthResize> resize = parseDepthResize(config.resize_depth);
  if (!resize) {
    throw InputError("parameter resize_depth: '" + config.resize_depth +
                     "' is not auto, yes or no");
  }
  s.resize_depth = *resize;
  s.backprojection.resize_to_render = resizesDepthToRender(s.resize_depth, s.splat.mode);
  s.backprojection.render_size = ImageSize{config.render_height, config.render_width};
  if (!(config.max_depth >= 0.0) || !(config.edge_threshold >= 0.0)) {
    throw InputError("parameters max_depth and edge_threshold must be >= 0");
  }
  s.backprojection.max_depth = static_cast<float>(config.max_depth);
  s.backprojection.edge_threshold = static_cast<float>(config.edge_threshold);
  if (config.threads < 0) throw InputError("parameter threads must be >= 0");
  s.threads = config.threads;
  return s;
}

void writeRendererSettingsToConfig(const ConditioningRendererSettings& s,
                                   ConditioningRendererConfig& config) {
  config.trajectory_source = s.source == TrajectorySource::kTf ? "tf" : "preset";
  config.world_frame = s.world_frame;
  config.keyframe_interval = s.keyframe_interval;
  config.preset = toString(s.preset);
  config.magnitude = s.magnitude;
  config.num_frames = s.num_frames;
  config.burst_frame_rate = s.burst_frame_rate;
  config.export_dir = s.export_dir;
  config.splat = toString(s.splat.mode);
  config.render_height = s.backprojection.render_size.height;
  config.render_width = s.backprojection.render_size.width;
  config.resize_depth = toString(s.resize_depth);
  config.max_depth = s.backprojection.max_depth;
  config.edge_threshold = s.backprojection.edge_threshold;
  config.threads = s.threads;
}

BackprojectionParams keyframeBackprojection(const ConditioningRendererSettings& settings,
                                            const ImageSize& grid) {
  BackprojectionParams params = settings.backprojection;
  params.resize_to_render =
      resizesDepthToRender(settings.resize_depth, settings.splat.mode, grid, params.render_size);
  return params;
}

namespace ros_conversions {

namespace enc = sensor_msgs::image_encodings;

const char* toString(RendererFault fault) {
  switch (fault) {
    case RendererFault::kNone:
      return "none";
    case RendererFault::kImageEncoding:
      return "image_encoding";
    case RendererFault::kImageStep:
      return "image_step";
    case RendererFault::kImageEmpty:
      return "image_empty";
    case RendererFault::kDepthImage:
      return "depth_image";
    case RendererFault::kMaskImage:
      return "mask_image";
    case RendererFault::kMaskSize:
      return "mask_size";
    case RendererFault::kGridSize:
      return "grid_size";
    case RendererFault::kCameraInfoIntrinsics:
      return "camera_info_intrinsics";
    case RendererFault::kCameraInfoSize:
      return "camera_info_size";
    case RendererFault::kTransformUnavailable:
      return "transform_unavailable";
    case RendererFault::kNoKeptPixel:
      return "no_kept_pixel";
  }
  return "unknown";
}

RendererStatus fromConversion(const ConversionStatus& status, const std::string& topic) {
  if (status.ok()) return RendererStatus::success();
  RendererFault fault = RendererFault::kImageEncoding;
  switch (status.fault) {
    case InputFault::kImageEncoding:
      fault = RendererFault::kImageEncoding;
      break;
    case InputFault::kImageStep:
      fault = RendererFault::kImageStep;
      break;
    case InputFault::kImageEmpty:
      fault = RendererFault::kImageEmpty;
      break;
    case InputFault::kCameraInfoIntrinsics:
    case InputFault::kCameraInfoDistortion:  // the camera model, as for K
      fault = RendererFault::kCameraInfoIntrinsics;
      break;
    case InputFault::kCameraInfoSize:
      fault = RendererFault::kCameraInfoSize;
      break;
    case InputFault::kTransformUnavailable:
      fault = RendererFault::kTransformUnavailable;
      break;
    default:  // cloud faults: the renderer reads no cloud
      break;
  }
  return RendererStatus::failure(fault, topic + ": " + status.reason);
}

using detail::emptyImage;
using detail::hostIsBigEndian;

namespace {

/// Size, step and data length of a single-channel image with `bytes` per pixel.
bool layoutOk(const sensor_msgs::Image& image, std::size_t bytes, std::string& why) {
  if (image.width == 0 || image.height == 0) {
    why = concat("is empty (", image.width, "x", image.height, ")");
    return false;
  }
  if (image.width > std::uint32_t(std::numeric_limits<int>::max() / 8) ||
      image.height > std::uint32_t(std::numeric_limits<int>::max())) {
    why = concat("size ", image.width, "x", image.height, " is too large");
    return false;
  }
  if (image.step < std::uint64_t(image.width) * bytes) {
    why =
        concat("step ", image.step, " is smaller than width ", image.width, " * ", bytes, " bytes");
    return false;
  }
  const std::uint64_t needed = std::uint64_t(image.step) * image.height;
  if (image.data.size() < needed) {
    why = concat("data has ", image.data.size(), " bytes, step ", image.step, " * height ",
                 image.height, " needs ", needed);
    return false;
  }
  if (bytes > 1 && bool(image.is_bigendian) != hostIsBigEndian()) {
    why = "byte order differs from the host's";
    return false;
  }
  return true;
}

RendererStatus checkDepth(const sensor_msgs::Image& depth) {
  std::size_t bytes = 0;
  if (depth.encoding == enc::TYPE_32FC1) {
    bytes = 4;
  } else if (depth.encoding == enc::TYPE_16UC1 || depth.encoding == enc::MONO16) {
    bytes = 2;
  } else {
    return RendererStatus::failure(
        RendererFault::kDepthImage,
        concat("depth/image encoding '", depth.encoding, "' is not 32FC1 (m) or 16UC1 (mm)"));
  }
  std::string why;
  if (!layoutOk(depth, bytes, why)) {
    return RendererStatus::failure(RendererFault::kDepthImage, "depth/image " + why);
  }
  return RendererStatus::success();
}

RendererStatus checkMask(const sensor_msgs::Image& mask, const ImageSize& depth_size) {
  if (mask.encoding != enc::MONO8 && mask.encoding != enc::TYPE_8UC1) {
    return RendererStatus::failure(
        RendererFault::kMaskImage,
        concat("depth/mask encoding '", mask.encoding, "' is not mono8 or 8UC1"));
  }
  std::string why;
  if (!layoutOk(mask, 1, why)) {
    return RendererStatus::failure(RendererFault::kMaskImage, "depth/mask " + why);
  }
  if (int(mask.width) != depth_size.width || int(mask.height) != depth_size.height) {
    return RendererStatus::failure(
        RendererFault::kMaskSize,
        concat("depth/mask is ", mask.width, "x", mask.height, " but depth/image is ",
               depth_size.width, "x", depth_size.height));
  }
  return RendererStatus::success();
}

/// Depth in metres, 0 where there is none. Call after checkDepth().
cv::Mat depthMetres(const sensor_msgs::Image& msg) {
  const int rows = int(msg.height), cols = int(msg.width);
  cv::Mat out(rows, cols, CV_32FC1);
  const bool millimetres = msg.encoding != enc::TYPE_32FC1;
  for (int r = 0; r < rows; ++r) {
    const std::uint8_t* row = msg.data.data() + std::size_t(r) * msg.step;
    float* dst = out.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      float z;
      if (millimetres) {
        std::uint16_t mm;
        std::memcpy(&mm, row + 2 * c, 2);
        z = mm * 0.001f;
      } else {
        std::memcpy(&z, row + 4 * c, 4);
      }
      dst[c] = std::isfinite(z) && z > 0.0f ? z : 0.0f;
    }
  }
  return out;
}

}  // namespace

RendererStatus gridStride(const ImageSize& image, const ImageSize& grid, int& stride) {
  if (const std::optional<StrideGrid> found = strideGridOfSize(image, grid)) {
    stride = found->stride;
    return RendererStatus::success();
  }
  return RendererStatus::failure(
      RendererFault::kGridSize,
      concat("depth/image is ", grid.width, "x", grid.height, " but image is ", image.width, "x",
             image.height, " (neither the same size nor a stride grid of it)"));
}

RendererStatus rendererInputFromMessages(const sensor_msgs::Image& image,
                                         const sensor_msgs::Image& depth,
                                         const sensor_msgs::Image& mask,
                                         const sensor_msgs::CameraInfo& depth_info,
                                         bool convert_pixels, RendererInput& out) {
  RendererStatus status = fromConversion(validateImage(image), "image");
  if (!status.ok()) return status;
  if (!(status = checkDepth(depth)).ok()) return status;
  const ImageSize grid{int(depth.height), int(depth.width)};
  if (!(status = checkMask(mask, grid)).ok()) return status;
  PinholeIntrinsics grid_k;
  status = fromConversion(intrinsicsFromCameraInfo(depth_info, grid, grid_k), "depth/camera_info");
  if (!status.ok()) return status;
  const ImageSize image_size{int(image.height), int(image.width)};
  int stride = 1;
  if (!(status = gridStride(image_size, grid, stride)).ok()) return status;

  out.header = image.header;
  out.image_size = image_size;
  out.grid_size = grid;
  out.stride = stride;
  out.grid_intrinsics = grid_k;
  const StrideGrid stride_grid{image_size, stride};
  out.image_intrinsics = stride_grid.imageIntrinsics(grid_k);
  out.image_bgr.release();
  out.grid_bgr.release();
  out.depth.release();
  out.kept.release();
  if (!convert_pixels) return RendererStatus::success();

  cv::Mat bgr;
  status = fromConversion(colourFromImage(image, ChannelOrder::kBgr, bgr), "image");
  if (!status.ok()) return status;
  // A copy either way: the message may go away (bgr8 is only wrapped).
  out.image_bgr = bgr.data == image.data.data() ? bgr.clone() : bgr;
  out.grid_bgr = sampleImageOnGrid(out.image_bgr, stride_grid);
  out.depth = depthMetres(depth);
  const cv::Mat wrapped(grid.height, grid.width, CV_8UC1,
                        const_cast<std::uint8_t*>(mask.data.data()), mask.step);
  out.kept = wrapped.clone();
  return RendererStatus::success();
}

// ---- Outputs

sensor_msgs::ImagePtr rgbImageFromBgr(const cv::Mat& bgr, const std_msgs::Header& header) {
  auto image = emptyImage(bgr.rows, bgr.cols, enc::RGB8, 3, header);
  cv::Mat view(bgr.rows, bgr.cols, CV_8UC3, image->data.data(), image->step);
  cv::cvtColor(bgr, view, cv::COLOR_BGR2RGB);
  return image;
}

sensor_msgs::ImagePtr monoImage(const cv::Mat& mono, const std_msgs::Header& header) {
  auto image = emptyImage(mono.rows, mono.cols, enc::MONO8, 1, header);
  cv::Mat view(mono.rows, mono.cols, CV_8UC1, image->data.data(), image->step);
  mono.copyTo(view);
  return image;
}

sensor_msgs::ImagePtr renderedDepthImage(const cv::Mat& depth, const cv::Mat& mask,
                                         const std_msgs::Header& header) {
  auto image = emptyImage(depth.rows, depth.cols, enc::TYPE_32FC1, sizeof(float), header);
  const float hole = std::numeric_limits<float>::quiet_NaN();
  for (int r = 0; r < depth.rows; ++r) {
    const float* z = depth.ptr<float>(r);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    std::uint8_t* dst = image->data.data() + std::size_t(r) * image->step;
    for (int c = 0; c < depth.cols; ++c) {
      const float value = m[c] ? z[c] : hole;
      std::memcpy(dst + sizeof(float) * c, &value, sizeof value);
    }
  }
  return image;
}

sensor_msgs::CameraInfoPtr renderedCameraInfo(const PinholeIntrinsics& k, const ImageSize& size,
                                              const std_msgs::Header& header) {
  auto info = boost::make_shared<sensor_msgs::CameraInfo>();
  info->header = header;
  info->height = size.height;
  info->width = size.width;
  info->distortion_model = "plumb_bob";
  info->D.assign(5, 0.0);
  info->K = {k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0};
  info->R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info->P = {k.fx, 0.0, k.cx, 0.0, 0.0, k.fy, k.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

}  // namespace ros_conversions
}  // namespace multimodal_nvs
