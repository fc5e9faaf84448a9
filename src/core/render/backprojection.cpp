#include "multimodal_nvs/core/render/backprojection.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

double ColoredCloud::medianDepth() const {
  if (z.empty()) return 0.0;
  std::vector<float> sorted(z);
  const std::size_t mid = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(mid), sorted.end());
  return sorted[mid];
}

cv::Mat sampleImageOnGrid(const cv::Mat& image_bgr, const StrideGrid& grid) {
  if (image_bgr.type() != CV_8UC3 || image_bgr.rows != grid.image.height ||
      image_bgr.cols != grid.image.width) {
    throw InputError("image to sample must be CV_8UC3 of the grid's image size");
  }
  if (grid.stride == 1) return image_bgr;
  cv::Mat out(grid.rows(), grid.cols(), CV_8UC3);
  for (int r = 0; r < out.rows; ++r) {
    const cv::Vec3b* src = image_bgr.ptr<cv::Vec3b>(r * grid.stride);
    cv::Vec3b* dst = out.ptr<cv::Vec3b>(r);
    for (int c = 0; c < out.cols; ++c)
      dst[c] = src[c * grid.stride];
  }
  return out;
}

namespace {

void requireDepth(const cv::Mat& depth) {
  if (depth.empty() || depth.type() != CV_32FC1) {
    throw InputError("depth map must be a non-empty single-channel float32 image");
  }
}

void requireMaskLike(const cv::Mat& valid, const cv::Mat& depth) {
  if (valid.empty()) return;
  if (valid.type() != CV_8UC1) throw InputError("valid mask must be uint8 (one channel)");
  if (valid.size() != depth.size()) {
    throw InputError("valid mask is " + std::to_string(valid.rows) + "x" +
                     std::to_string(valid.cols) + " but the depth map is " +
                     std::to_string(depth.rows) + "x" + std::to_string(depth.cols));
  }
}

/// Depth where kept, 0 elsewhere (also for NaN and negative values).
cv::Mat keptDepth(const cv::Mat& depth, const cv::Mat& valid) {
  cv::Mat out(depth.size(), CV_32FC1);
  for (int r = 0; r < depth.rows; ++r) {
    const float* d = depth.ptr<float>(r);
    const std::uint8_t* m = valid.empty() ? nullptr : valid.ptr<std::uint8_t>(r);
    float* o = out.ptr<float>(r);
    for (int c = 0; c < depth.cols; ++c) {
      const bool keep = (m == nullptr || m[c] != 0) && d[c] > 0.0f && std::isfinite(d[c]);
      o[c] = keep ? d[c] : 0.0f;
    }
  }
  return out;
}

}  // namespace

cv::Mat scatterDepthNearest(const cv::Mat& depth, const cv::Mat& valid, ImageSize to) {
  requireDepth(depth);
  requireMaskLike(valid, depth);
  if (to.height <= 0 || to.width <= 0) throw InputError("render size must be positive");
  cv::Mat out = cv::Mat::zeros(to.height, to.width, CV_32FC1);
  const double sx = static_cast<double>(to.width) / depth.cols;
  const double sy = static_cast<double>(to.height) / depth.rows;
  for (int r = 0; r < depth.rows; ++r) {
    const float* d = depth.ptr<float>(r);
    const std::uint8_t* m = valid.empty() ? nullptr : valid.ptr<std::uint8_t>(r);
    const int tr = std::min(to.height - 1, static_cast<int>(std::lround(r * sy)));
    float* o = out.ptr<float>(tr);
    for (int c = 0; c < depth.cols; ++c) {
      if ((m != nullptr && m[c] == 0) || !(d[c] > 0.0f) || !std::isfinite(d[c])) continue;
      const int tc = std::min(to.width - 1, static_cast<int>(std::lround(c * sx)));
      o[tc] = d[c];
    }
  }
  return out;
}

cv::Mat reliableDepthMask(const cv::Mat& depth, float threshold, int window) {
  requireDepth(depth);
  if (window < 1 || window % 2 == 0) throw InputError("depth-edge window must be odd and >= 1");
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(window, window));
  cv::Mat local_max, local_min, local_sum;
  // Pixels outside the image must not take part in max/min (max pooling pads with -inf).
  cv::dilate(depth, local_max, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT,
             cv::Scalar(-INFINITY));
  cv::erode(depth, local_min, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT,
            cv::Scalar(INFINITY));
  // Average pooling counts the zero padding in the mean.
  cv::boxFilter(depth, local_sum, CV_32F, cv::Size(window, window), cv::Point(-1, -1), true,
                cv::BORDER_CONSTANT);
  cv::Mat mask(depth.size(), CV_8UC1);
  for (int r = 0; r < depth.rows; ++r) {
    const float* d = depth.ptr<float>(r);
    const float* hi = local_max.ptr<float>(r);
    const float* lo = local_min.ptr<float>(r);
    const float* mean = local_sum.ptr<float>(r);
    std::uint8_t* o = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < depth.cols; ++c) {
      const float ratio = (hi[c] - lo[c]) / (mean[c] + 1e-6f);
      o[c] = (d[c] > 0.0f && ratio < threshold) ? 1 : 0;
    }
  }
  return mask;
}

ColoredCloud backproject(const cv::Mat& depth, const cv::Mat& image_bgr,
                         const PinholeIntrinsics& k) {
  requireDepth(depth);
  if (image_bgr.type() != CV_8UC3) throw InputError("image must be 8-bit with 3 channels");
  if (image_bgr.size() != depth.size()) {
    throw InputError("image is " + std::to_string(image_bgr.rows) + "x" +
                     std::to_string(image_bgr.cols) + " but the depth map is " +
                     std::to_string(depth.rows) + "x" + std::to_string(depth.cols));
  }
  k.validate("back-projection intrinsics");
  ColoredCloud cloud;
  cloud.intrinsics = k;
  cloud.grid = {depth.rows, depth.cols};
  const std::size_t count = static_cast<std::size_t>(cv::countNonZero(depth > 0.0f));
  cloud.x.reserve(count);
  cloud.y.reserve(count);
  cloud.z.reserve(count);
  cloud.bgr.reserve(count);
  if (k.distortion.any()) {
    // Each kept pixel's ray through the lens model, undistorted in one batch.
    std::vector<Eigen::Vector2d> rays;
    rays.reserve(count);
    for (int v = 0; v < depth.rows; ++v) {
      const float* d = depth.ptr<float>(v);
      for (int u = 0; u < depth.cols; ++u) {
        if (d[u] > 0.0f && std::isfinite(d[u])) rays.emplace_back(u, v);
      }
    }
    std::vector<Eigen::Vector2d> pixels = rays;
    k.normalisedRays(rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const int u = static_cast<int>(pixels[i].x()), v = static_cast<int>(pixels[i].y());
      const float z = depth.at<float>(v, u);
      const cv::Vec3b& c = image_bgr.at<cv::Vec3b>(v, u);
      cloud.x.push_back(static_cast<float>(z * rays[i].x()));
      cloud.y.push_back(static_cast<float>(z * rays[i].y()));
      cloud.z.push_back(z);
      cloud.bgr.push_back(std::uint32_t(c[0]) | std::uint32_t(c[1]) << 8 |
                          std::uint32_t(c[2]) << 16);
    }
    return cloud;
  }
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const cv::Vec3b* c = image_bgr.ptr<cv::Vec3b>(v);
    const double ray_y = (v - k.cy) / k.fy;
    for (int u = 0; u < depth.cols; ++u) {
      if (!(d[u] > 0.0f) || !std::isfinite(d[u])) continue;
      const double z = d[u];
      cloud.x.push_back(static_cast<float>(z * (u - k.cx) / k.fx));
      cloud.y.push_back(static_cast<float>(z * ray_y));
      cloud.z.push_back(d[u]);
      cloud.bgr.push_back(std::uint32_t(c[u][0]) | std::uint32_t(c[u][1]) << 8 |
                          std::uint32_t(c[u][2]) << 16);
    }
  }
  return cloud;
}

ColoredCloud buildColoredCloud(const cv::Mat& depth, const cv::Mat& valid, const cv::Mat& image_bgr,
                               const PinholeIntrinsics& k, const BackprojectionParams& params) {
  requireDepth(depth);
  requireMaskLike(valid, depth);
  if (image_bgr.empty() || image_bgr.type() != CV_8UC3) {
    throw InputError("image must be a non-empty 8-bit 3-channel image");
  }
  if (image_bgr.size() != depth.size()) {
    throw InputError("image is " + std::to_string(image_bgr.rows) + "x" +
                     std::to_string(image_bgr.cols) + " but the depth map is " +
                     std::to_string(depth.rows) + "x" + std::to_string(depth.cols) +
                     " (they must describe the same pixel grid)");
  }
  cv::Mat kept;
  cv::Mat image = image_bgr;
  PinholeIntrinsics grid_k = k;
  if (params.resize_to_render) {
    const ImageSize to = params.render_size;
    if (depth.rows >= to.height && depth.cols >= to.width) {
      kept = scatterDepthNearest(depth, valid, to);  // GEN3C's own downsizing
    } else {
      // Upsizing (e.g. a stride-2 depth grid to 704x1280): a scatter would leave empty rows and
      // columns that the depth-edge filter then takes for edges, dropping almost every point.
      cv::resize(keptDepth(depth, valid), kept, cv::Size(to.width, to.height), 0, 0,
                 cv::INTER_NEAREST);
    }
    cv::resize(image_bgr, image, cv::Size(to.width, to.height), 0, 0, cv::INTER_LINEAR);
    grid_k = k.scaledTo(depth.rows, depth.cols, to.height, to.width);
  } else {
    kept = keptDepth(depth, valid);
  }
  if (params.max_depth > 0.0f) {
    cv::min(kept, params.max_depth, kept);  // kept is >= 0 already: the lower clamp is implied
  }
  if (params.edge_threshold > 0.0f) {
    const cv::Mat reliable = reliableDepthMask(kept, params.edge_threshold, params.edge_window);
    kept.setTo(0.0f, reliable == 0);
  }
  ColoredCloud cloud = backproject(kept, image, grid_k);
  if (cloud.size() == 0) {
    throw InputError(
        "no kept pixel: the depth/valid mask is empty after clamping and the "
        "depth-edge filter");
  }
  return cloud;
}

}  // namespace multimodal_nvs
