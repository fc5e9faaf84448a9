#include "multimodal_nvs/ros/conversions.hpp"

#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/point_field_conversion.h>
#include <algorithm>
#include <boost/make_shared.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "message_helpers.hpp"
#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

namespace enc = sensor_msgs::image_encodings;
using detail::concat;
using detail::hostIsBigEndian;

const char* toString(InputFault fault) {
  switch (fault) {
    case InputFault::kNone:
      return "none";
    case InputFault::kCloudMissingField:
      return "cloud_missing_field";
    case InputFault::kCloudFieldDatatype:
      return "cloud_field_datatype";
    case InputFault::kCloudFieldCount:
      return "cloud_field_count";
    case InputFault::kCloudFieldOffset:
      return "cloud_field_offset";
    case InputFault::kCloudLayout:
      return "cloud_layout";
    case InputFault::kCloudDataTooShort:
      return "cloud_data_too_short";
    case InputFault::kCloudBigEndian:
      return "cloud_big_endian";
    case InputFault::kCloudEmpty:
      return "cloud_empty";
    case InputFault::kCloudNoFinitePoint:
      return "cloud_no_finite_point";
    case InputFault::kImageEncoding:
      return "image_encoding";
    case InputFault::kImageStep:
      return "image_step";
    case InputFault::kImageEmpty:
      return "image_empty";
    case InputFault::kImageDecode:
      return "image_decode";
    case InputFault::kCameraInfoIntrinsics:
      return "camera_info_intrinsics";
    case InputFault::kCameraInfoSize:
      return "camera_info_size";
    case InputFault::kCameraInfoDistortion:
      return "camera_info_distortion";
    case InputFault::kCloudBehindCamera:
      return "cloud_behind_camera";
    case InputFault::kTransformUnavailable:
      return "transform_unavailable";
    case InputFault::kStampNotNewer:
      return "stamp_not_newer";
    case InputFault::kOutOfMemory:
      return "out_of_memory";
  }
  return "unknown";
}

namespace {

/// Where x, y and z live inside one point record.
struct XyzLayout {
  std::uint32_t offset[3];
  std::uint8_t datatype[3];
};

ConversionStatus findXyz(const sensor_msgs::PointCloud2& cloud, XyzLayout& layout) {
  static const char* const kNames[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    const sensor_msgs::PointField* field = nullptr;
    for (const auto& f : cloud.fields) {
      if (f.name == kNames[axis]) {
        field = &f;
        break;
      }
    }
    if (!field) {
      return ConversionStatus::failure(InputFault::kCloudMissingField,
                                       concat("PointCloud2 has no '", kNames[axis], "' field"));
    }
    if (field->datatype != sensor_msgs::PointField::FLOAT32 &&
        field->datatype != sensor_msgs::PointField::FLOAT64) {
      return ConversionStatus::failure(
          InputFault::kCloudFieldDatatype,
          concat("PointCloud2 field '", kNames[axis], "' has datatype ", int(field->datatype),
                 " (expected FLOAT32=7 or FLOAT64=8)"));
    }
    if (field->count != 1) {
      return ConversionStatus::failure(InputFault::kCloudFieldCount,
                                       concat("PointCloud2 field '", kNames[axis], "' has count ",
                                              field->count, " (expected 1)"));
    }
    const std::uint64_t size = field->datatype == sensor_msgs::PointField::FLOAT32 ? 4 : 8;
    if (std::uint64_t(field->offset) + size > cloud.point_step) {
      return ConversionStatus::failure(
          InputFault::kCloudFieldOffset,
          concat("PointCloud2 field '", kNames[axis], "' at offset ", field->offset, " + ", size,
                 " bytes exceeds point_step ", cloud.point_step));
    }
    layout.offset[axis] = field->offset;
    layout.datatype[axis] = field->datatype;
  }
  return ConversionStatus::success();
}

inline double readCoordinate(const std::uint8_t* record, std::uint32_t offset,
                             std::uint8_t datatype) {
  if (datatype == sensor_msgs::PointField::FLOAT32) {
    float value;
    std::memcpy(&value, record + offset, sizeof value);
    return value;
  }
  double value;
  std::memcpy(&value, record + offset, sizeof value);
  return value;
}

/// Calls visit(x, y, z) for every point of a validated cloud, row by row.
template <typename Visit>
void forEachPoint(const sensor_msgs::PointCloud2& cloud, const XyzLayout& layout, Visit&& visit) {
  for (std::uint32_t row = 0; row < cloud.height; ++row) {
    const std::uint8_t* record = cloud.data.data() + std::size_t(row) * cloud.row_step;
    for (std::uint32_t col = 0; col < cloud.width; ++col, record += cloud.point_step) {
      visit(readCoordinate(record, layout.offset[0], layout.datatype[0]),
            readCoordinate(record, layout.offset[1], layout.datatype[1]),
            readCoordinate(record, layout.offset[2], layout.datatype[2]));
    }
  }
}

ConversionStatus validateCloud(const sensor_msgs::PointCloud2& cloud, XyzLayout& layout) {
  ConversionStatus status = findXyz(cloud, layout);
  if (!status.ok()) return status;
  if (bool(cloud.is_bigendian) != hostIsBigEndian()) {
    return ConversionStatus::failure(
        InputFault::kCloudBigEndian,
        concat("PointCloud2 is ", cloud.is_bigendian ? "big" : "little",
               "-endian and this host is not; byte swapping is not supported"));
  }
  // 32-bit factors: every product below is exact in 64 bits, so nothing can wrap around.
  const std::uint64_t points = std::uint64_t(cloud.width) * cloud.height;
  if (points == 0) {
    return ConversionStatus::failure(
        InputFault::kCloudEmpty,
        concat("PointCloud2 is empty (", cloud.width, "x", cloud.height, ")"));
  }
  if (std::uint64_t(cloud.width) * cloud.point_step > cloud.row_step) {
    return ConversionStatus::failure(
        InputFault::kCloudLayout, concat("PointCloud2 width ", cloud.width, " * point_step ",
                                         cloud.point_step, " exceeds row_step ", cloud.row_step));
  }
  const std::uint64_t needed = std::uint64_t(cloud.row_step) * cloud.height;
  if (needed > std::numeric_limits<std::size_t>::max() ||
      points > std::numeric_limits<std::size_t>::max() / sizeof(Eigen::Vector3d)) {
    return ConversionStatus::failure(InputFault::kCloudLayout,
                                     concat("PointCloud2 size ", cloud.width, "x", cloud.height,
                                            " does not fit in memory on this host"));
  }
  if (cloud.data.size() < needed) {
    return ConversionStatus::failure(
        InputFault::kCloudDataTooShort,
        concat("PointCloud2 data has ", cloud.data.size(), " bytes, row_step ", cloud.row_step,
               " * height ", cloud.height, " needs ", needed));
  }
  return ConversionStatus::success();
}

}  // namespace

ConversionStatus validateCloudLayout(const sensor_msgs::PointCloud2& cloud) {
  XyzLayout layout;
  return validateCloud(cloud, layout);
}

ConversionStatus pointsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                 const Eigen::Isometry3d& sensor_to_camera,
                                 std::vector<Eigen::Vector3d>& points, std::size_t* non_finite) {
  return pointsFromCloud(cloud, sensor_to_camera, 0, points, non_finite, nullptr);
}

ConversionStatus pointsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                 const Eigen::Isometry3d& sensor_to_camera, std::size_t max_points,
                                 std::vector<Eigen::Vector3d>& points, std::size_t* non_finite,
                                 std::size_t* subsampled) {
  points.clear();
  XyzLayout layout;
  ConversionStatus status = validateCloud(cloud, layout);
  if (!status.ok()) return status;
  const std::size_t records = std::size_t(cloud.width) * cloud.height;
  const std::size_t step =
      max_points > 0 && records > max_points ? (records + max_points - 1) / max_points : 1;
  if (subsampled) *subsampled = step;
  points.reserve((records + step - 1) / step);
  std::size_t skipped = 0, index = 0;
  forEachPoint(cloud, layout, [&](double x, double y, double z) {
    if (index++ % step != 0) return;
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      ++skipped;
      return;
    }
    points.push_back(sensor_to_camera * Eigen::Vector3d(x, y, z));
  });
  if (non_finite) *non_finite = skipped;
  if (points.empty()) {
    return ConversionStatus::failure(InputFault::kCloudNoFinitePoint,
                                     concat("PointCloud2 has ", skipped, step > 1 ? " sampled" : "",
                                            " points and none has finite x, y, z"));
  }
  return ConversionStatus::success();
}

ConversionStatus checkPointsInFront(const std::vector<Eigen::Vector3d>& points_camera) {
  for (const auto& p : points_camera) {
    if (p.z() > 0.0) return ConversionStatus::success();
  }
  return ConversionStatus::failure(
      InputFault::kCloudBehindCamera,
      concat("none of the ", points_camera.size(),
             " finite points is in front of the camera (z > 0 in the image frame)"));
}

ConversionStatus pointsFromCloud(const sensor_msgs::PointCloud2& cloud,
                                 std::vector<Eigen::Vector3f>& points) {
  std::vector<Eigen::Vector3d> points_double;
  ConversionStatus status =
      pointsFromCloud(cloud, Eigen::Isometry3d::Identity(), points_double, nullptr);
  points.clear();
  points.reserve(points_double.size());
  for (const auto& p : points_double)
    points.push_back(p.cast<float>());
  return status;
}

namespace {

/// Channels of a supported 8-bit colour or mono encoding, 0 for anything else.
int supportedChannels(const std::string& encoding) {
  if (encoding == enc::RGB8 || encoding == enc::BGR8) return 3;
  if (encoding == enc::RGBA8 || encoding == enc::BGRA8) return 4;
  if (encoding == enc::MONO8) return 1;
  return 0;
}

}  // namespace

ConversionStatus validateImage(const sensor_msgs::Image& image) {
  const int channels = supportedChannels(image.encoding);
  if (channels == 0) {
    return ConversionStatus::failure(
        InputFault::kImageEncoding,
        concat("Image encoding '", image.encoding,
               "' is not supported (expected rgb8, bgr8, rgba8, bgra8 or mono8)"));
  }
  if (image.width == 0 || image.height == 0) {
    return ConversionStatus::failure(
        InputFault::kImageEmpty, concat("Image is empty (", image.width, "x", image.height, ")"));
  }
  // Rows are addressed with int by OpenCV.
  if (image.width > std::uint32_t(std::numeric_limits<int>::max() / 4) ||
      image.height > std::uint32_t(std::numeric_limits<int>::max())) {
    return ConversionStatus::failure(InputFault::kImageStep, concat("Image size ", image.width, "x",
                                                                    image.height, " is too large"));
  }
  const std::uint64_t min_step = std::uint64_t(image.width) * channels;
  if (image.step < min_step) {
    return ConversionStatus::failure(InputFault::kImageStep,
                                     concat("Image step ", image.step, " is smaller than width ",
                                            image.width, " * ", channels, " channels"));
  }
  const std::uint64_t needed = std::uint64_t(image.step) * image.height;
  if (image.data.size() < needed) {
    return ConversionStatus::failure(
        InputFault::kImageStep, concat("Image data has ", image.data.size(), " bytes, step ",
                                       image.step, " * height ", image.height, " needs ", needed));
  }
  return ConversionStatus::success();
}

ConversionStatus colourFromImage(const sensor_msgs::Image& image, ChannelOrder order,
                                 cv::Mat& out) {
  ConversionStatus status = validateImage(image);
  if (!status.ok()) return status;
  const int channels = supportedChannels(image.encoding);
  // The Mat header only wraps the message buffer; it is never written through.
  const cv::Mat wrapped(int(image.height), int(image.width), CV_8UC(channels),
                        const_cast<std::uint8_t*>(image.data.data()), image.step);
  const bool rgb = order == ChannelOrder::kRgb;
  if (image.encoding == (rgb ? enc::RGB8 : enc::BGR8)) {
    out = wrapped;
  } else if (image.encoding == enc::RGB8 || image.encoding == enc::BGR8) {
    cv::cvtColor(wrapped, out, cv::COLOR_RGB2BGR);  // the same swap either way
  } else if (image.encoding == enc::RGBA8) {
    cv::cvtColor(wrapped, out, rgb ? cv::COLOR_RGBA2RGB : cv::COLOR_RGBA2BGR);
  } else if (image.encoding == enc::BGRA8) {
    cv::cvtColor(wrapped, out, rgb ? cv::COLOR_BGRA2RGB : cv::COLOR_BGRA2BGR);
  } else {
    cv::cvtColor(wrapped, out, rgb ? cv::COLOR_GRAY2RGB : cv::COLOR_GRAY2BGR);
  }
  return ConversionStatus::success();
}

ConversionStatus bgrFromCompressed(const sensor_msgs::CompressedImage& image, cv::Mat& bgr) {
  bgr.release();
  if (!image.data.empty()) {
    try {
      const cv::Mat payload(1, int(image.data.size()), CV_8UC1,
                            const_cast<std::uint8_t*>(image.data.data()));
      bgr = cv::imdecode(payload, cv::IMREAD_COLOR);
    } catch (const cv::Exception& e) {
      bgr.release();
    }
  }
  if (bgr.empty()) {
    return ConversionStatus::failure(
        InputFault::kImageDecode, concat("CompressedImage (format '", image.format, "', ",
                                         image.data.size(), " bytes) is not a decodable jpeg/png"));
  }
  return ConversionStatus::success();
}

ConversionStatus intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info,
                                          const ImageSize& image_size,
                                          PinholeIntrinsics& intrinsics) {
  if (int(info.width) != image_size.width || int(info.height) != image_size.height) {
    return ConversionStatus::failure(
        InputFault::kCameraInfoSize,
        concat("CameraInfo size ", info.width, "x", info.height, " differs from the image's ",
               image_size.width, "x", image_size.height));
  }
  const auto& k = info.K;
  PinholeIntrinsics candidate{k[0], k[4], k[2], k[5]};
  try {
    candidate.validate("CameraInfo K");
  } catch (const InputError& e) {
    return ConversionStatus::failure(InputFault::kCameraInfoIntrinsics, e.what());
  }
  try {
    candidate.distortion = LensDistortion::fromRos(info.distortion_model, info.D, "CameraInfo");
  } catch (const InputError& e) {
    return ConversionStatus::failure(InputFault::kCameraInfoDistortion, e.what());
  }
  if (k[1] != 0.0 || k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0) {
    return ConversionStatus::failure(
        InputFault::kCameraInfoIntrinsics,
        concat("CameraInfo K is not [fx 0 cx; 0 fy cy; 0 0 1] (skew ", k[1], ", K[8] ", k[8], ")"));
  }
  if (info.binning_x > 1 || info.binning_y > 1 || info.roi.width != 0 || info.roi.height != 0) {
    return ConversionStatus::failure(InputFault::kCameraInfoIntrinsics,
                                     "CameraInfo with binning or ROI is not supported");
  }
  intrinsics = candidate;
  return ConversionStatus::success();
}

namespace {

void shapeGridImage(sensor_msgs::Image& image, const StrideGrid& grid, const std::string& encoding,
                    int bytes_per_pixel, const std_msgs::Header& header) {
  detail::shapeImage(image, grid.rows(), grid.cols(), encoding, bytes_per_pixel, header);
}

// Restrict-pointer loops: written through the message's byte vector, the stores may alias the
// DepthMap's vectors, and GCC then reloads their data pointers per pixel and keeps the loop scalar.
void maskedDepth(const float* __restrict depth, const std::uint8_t* __restrict valid,
                 std::size_t count, std::uint8_t* __restrict out) {
  const float not_kept = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < count; ++i) {
    const float value = valid[i] ? depth[i] : not_kept;
    std::memcpy(out + i * sizeof(float), &value, sizeof value);
  }
}

void maskBytes(const std::uint8_t* __restrict valid, std::size_t count,
               std::uint8_t* __restrict out) {
  for (std::size_t i = 0; i < count; ++i) {
    out[i] = valid[i] ? 255 : 0;
  }
}
}  // namespace

void depthImage(const DepthMap& depth, const std_msgs::Header& header, sensor_msgs::Image& image) {
  shapeGridImage(image, depth.grid, enc::TYPE_32FC1, sizeof(float), header);
  maskedDepth(depth.depth.data(), depth.valid.data(), depth.depth.size(), image.data.data());
}

void varianceImage(const DepthMap& depth, const std_msgs::Header& header,
                   sensor_msgs::Image& image) {
  shapeGridImage(image, depth.grid, enc::TYPE_32FC1, sizeof(float), header);
  std::memcpy(image.data.data(), depth.variance.data(), depth.variance.size() * sizeof(float));
}

void maskImage(const DepthMap& depth, const std_msgs::Header& header, sensor_msgs::Image& image) {
  shapeGridImage(image, depth.grid, enc::MONO8, 1, header);
  maskBytes(depth.valid.data(), depth.valid.size(), image.data.data());
}

sensor_msgs::CameraInfoPtr gridCameraInfo(const sensor_msgs::CameraInfo& full,
                                          const StrideGrid& grid) {
  auto info = boost::make_shared<sensor_msgs::CameraInfo>(full);
  info->width = grid.cols();
  info->height = grid.rows();
  const double s = grid.stride;
  for (int i : {0, 2, 4, 5})
    info->K[i] /= s;
  for (int i : {0, 2, 3, 5, 6, 7})
    info->P[i] /= s;
  return info;
}

sensor_msgs::PointCloud2 float32Cloud(const std::vector<std::string>& names,
                                      const std::vector<float>& values,
                                      const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  for (std::size_t i = 0; i < names.size(); ++i) {
    sensor_msgs::PointField field;
    field.name = names[i];
    field.offset = static_cast<std::uint32_t>(4 * i);
    field.datatype = sensor_msgs::PointField::FLOAT32;
    field.count = 1;
    cloud.fields.push_back(field);
  }
  cloud.point_step = static_cast<std::uint32_t>(4 * names.size());
  cloud.height = 1;
  cloud.width = names.empty() ? 0 : static_cast<std::uint32_t>(values.size() / names.size());
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_bigendian = false;
  cloud.is_dense =
      std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
  cloud.data.resize(std::size_t(cloud.row_step));
  if (!cloud.data.empty()) std::memcpy(cloud.data.data(), values.data(), cloud.data.size());
  return cloud;
}

void coloredCloud(const DepthMap& depth, const PinholeIntrinsics& intrinsics, const cv::Mat& rgb,
                  int cloud_stride, const std_msgs::Header& header, sensor_msgs::PointCloud2& cloud,
                  ThreadPool* pool) {
  cloud.header = header;
  // stddev after rgb: readers that know XYZRGB (PCL, the renderer) find x, y, z, rgb where they
  // were; rviz colours the cloud by it with the Intensity transformer.
  constexpr int kFields = 5;
  cloud.fields.resize(kFields);
  const char* const names[kFields] = {"x", "y", "z", "rgb", "stddev"};
  for (int i = 0; i < kFields; ++i) {
    cloud.fields[i].name = names[i];
    cloud.fields[i].offset = 4 * i;
    cloud.fields[i].datatype = sensor_msgs::PointField::FLOAT32;
    cloud.fields[i].count = 1;
  }
  cloud.point_step = 4 * kFields;
  cloud.is_bigendian = hostIsBigEndian();
  cloud.is_dense = true;
  cloud.height = 1;

  const StrideGrid& grid = depth.grid;
  const int step = std::max(1, cloud_stride);
  const int cols = grid.cols();
  const long long cloud_rows = (grid.rows() + step - 1) / step;
  const bool has_colour =
      rgb.type() == CV_8UC3 && rgb.rows == grid.image.height && rgb.cols == grid.image.width;
  // Each cloud row's first point (prefix sums of the kept pixels per row), so that rows can be
  // written in parallel: a full-resolution cloud is ~2 M points, ~11 ms on one core.
  std::vector<std::size_t> row_start(std::size_t(cloud_rows) + 1, 0);
  parallelForOrInline(
      pool, cloud_rows,
      [&](long long i, int) {
        const std::uint8_t* valid = depth.valid.data() + std::size_t(i) * step * cols;
        std::size_t count = 0;
        for (int c = 0; c < cols; c += step)
          count += valid[c];
        row_start[std::size_t(i) + 1] = count;
      },
      16);
  for (std::size_t i = 1; i < row_start.size(); ++i)
    row_start[i] += row_start[i - 1];
  const std::size_t count = row_start.back();
  detail::resizeKeepingBuffer(cloud.data, count * cloud.point_step);
  // A distorted camera's rays (the pixel rays undistorted in one batch, in cloud order; pinhole:
  // K's division).
  std::vector<Eigen::Vector2d> rays;
  if (intrinsics.distortion.any()) {
    rays.reserve(count);
    for (int r = 0; r < grid.rows(); r += step) {
      for (int c = 0; c < cols; c += step) {
        if (depth.valid[std::size_t(r) * cols + c]) {
          rays.emplace_back(c * grid.stride, r * grid.stride);
        }
      }
    }
    intrinsics.normalisedRays(rays);
  }
  const std::size_t point_step = cloud.point_step;
  parallelForOrInline(
      pool, cloud_rows,
      [&](long long i, int) {
        const int r = static_cast<int>(i) * step;
        const int v = r * grid.stride;
        std::size_t point = row_start[std::size_t(i)];
        std::uint8_t* out = cloud.data.data() + point * point_step;
        for (int c = 0; c < cols; c += step) {
          const std::size_t index = std::size_t(r) * cols + c;
          if (!depth.valid[index]) continue;
          const int u = c * grid.stride;
          const double z = depth.depth[index];
          float xyz[3] = {float((u - intrinsics.cx) * z / intrinsics.fx),
                          float((v - intrinsics.cy) * z / intrinsics.fy), float(z)};
          if (!rays.empty()) {
            const Eigen::Vector2d& ray = rays[point];
            xyz[0] = float(ray.x() * z);
            xyz[1] = float(ray.y() * z);
          }
          std::uint32_t packed = 0;
          if (has_colour) {
            const cv::Vec3b& px = rgb.at<cv::Vec3b>(v, u);
            packed = (std::uint32_t(px[0]) << 16) | (std::uint32_t(px[1]) << 8) | px[2];
          }
          std::memcpy(out, xyz, sizeof xyz);
          std::memcpy(out + 12, &packed, sizeof packed);
          // Kept pixels have a finite variance (only finite variances are candidates for keeping).
          const float stddev = std::sqrt(depth.variance[index]);
          std::memcpy(out + 16, &stddev, sizeof stddev);
          out += point_step;
          ++point;
        }
      },
      16);
  cloud.width = static_cast<std::uint32_t>(count);
  cloud.row_step = cloud.width * cloud.point_step;
}

ConversionStatus frameImage(const sensor_msgs::Image& image, FrameImage& frame) {
  ConversionStatus status = validateImage(image);
  if (!status.ok()) return status;
  frame.header = image.header;
  frame.size = ImageSize{int(image.height), int(image.width)};
  frame.rgb = [&image](cv::Mat& rgb) { return colourFromImage(image, ChannelOrder::kRgb, rgb); };
  frame.bgr = [&image](cv::Mat& bgr) { return colourFromImage(image, ChannelOrder::kBgr, bgr); };
  return status;
}

ConversionStatus frameImage(const sensor_msgs::CompressedImage& image, FrameImage& frame) {
  cv::Mat decoded;  // OpenCV decodes into BGR
  ConversionStatus status = bgrFromCompressed(image, decoded);
  if (!status.ok()) return status;
  frame.header = image.header;
  frame.size = ImageSize{decoded.rows, decoded.cols};
  frame.rgb = [decoded](cv::Mat& rgb) {
    cv::cvtColor(decoded, rgb, cv::COLOR_BGR2RGB);
    return ConversionStatus::success();
  };
  frame.bgr = [decoded](cv::Mat& bgr) {
    bgr = decoded;
    return ConversionStatus::success();
  };
  return status;
}

}  // namespace ros_conversions
}  // namespace multimodal_nvs
