#include "multimodal_nvs/core/splatting.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "multimodal_nvs/core/errors.hpp"

namespace multimodal_nvs {

SplatMode parseSplatMode(const std::string& name) {
  if (name == "gen3c") return SplatMode::kGen3c;
  if (name == "zbuffer") return SplatMode::kZbuffer;
  throw InputError("unknown splat mode '" + name + "' (valid: gen3c, zbuffer)");
}

std::string toString(SplatMode mode) { return mode == SplatMode::kGen3c ? "gen3c" : "zbuffer"; }

namespace {

/// The rigid transform and intrinsics of one target view in float, as the inner loops use them.
struct ViewTransform {
  float r[9];
  float t[3];
  float fx, fy, cx, cy;

  explicit ViewTransform(const TargetCamera& camera) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r[3 * i + j] = static_cast<float>(camera.world_to_camera(i, j));
      t[i] = static_cast<float>(camera.world_to_camera(i, 3));
    }
    fx = static_cast<float>(camera.intrinsics.fx);
    fy = static_cast<float>(camera.intrinsics.fy);
    cx = static_cast<float>(camera.intrinsics.cx);
    cy = static_cast<float>(camera.intrinsics.cy);
  }
};

constexpr std::uint64_t kEmptyKey = std::numeric_limits<std::uint64_t>::max();

inline std::uint32_t floatBits(float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

inline float bitsToFloat(std::uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

void allocate(RenderedFrame& out, ImageSize size, bool with_signed) {
  out.bgr.create(size.height, size.width, CV_8UC3);
  out.mask.create(size.height, size.width, CV_8UC1);
  out.depth.create(size.height, size.width, CV_32FC1);
  if (with_signed) {
    out.signed_bgr.create(size.height, size.width, CV_32FC3);
  } else {
    out.signed_bgr.release();
  }
}

}  // namespace

float maxTargetDepth(const ColoredCloud& cloud, const TargetCamera& camera) {
  const ViewTransform view(camera);
  const std::size_t n = cloud.size();
  const float* x = cloud.x.data();
  const float* y = cloud.y.data();
  const float* z = cloud.z.data();
  float best = -std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    best = std::max(best, view.r[6] * x[i] + view.r[7] * y[i] + view.r[8] * z[i] + view.t[2]);
  }
  return best;
}

PointSplatter::PointSplatter(int threads) : pool_(threads) {
  depth_keys_.resize(static_cast<std::size_t>(pool_.size()));
  accumulators_.resize(static_cast<std::size_t>(pool_.size()));
}

std::vector<RenderedFrame> PointSplatter::render(const ColoredCloud& cloud,
                                                 const Trajectory& trajectory, int first,
                                                 int count, const SplatParams& params) {
  std::vector<RenderedFrame> frames;
  render(cloud, trajectory, first, count, params, frames);
  return frames;
}

void PointSplatter::render(const ColoredCloud& cloud, const Trajectory& trajectory, int first,
                           int count, const SplatParams& params,
                           std::vector<RenderedFrame>& frames) {
  const int total = static_cast<int>(trajectory.cameras.size());
  if (first < 0 || count < 0 || first + count > total) {
    throw InputError("frames " + std::to_string(first) + ".." + std::to_string(first + count - 1) +
                     " are outside the trajectory of " + std::to_string(total) + " frames");
  }
  if (cloud.size() == 0) throw InputError("nothing to render: the coloured cloud is empty");
  if (cloud.size() >= kEmptyKey >> 32) throw InputError("cloud has too many points (>= 2^32)");
  if (trajectory.size.height <= 0 || trajectory.size.width <= 0) {
    throw InputError("render size must be positive");
  }
  if (params.gen3c_batch < 1) throw InputError("gen3c batch size must be >= 1");
  if (params.max_footprint < 1) throw InputError("maximum splat footprint must be >= 1");
  frames.resize(static_cast<std::size_t>(count));
  if (count == 0) return;

  std::vector<float> max_log_depth;  // per requested frame, gen3c only
  if (params.mode == SplatMode::kGen3c) {
    // The normaliser spans every frame of a GEN3C batch, also those outside the requested range,
    // so a frame renders the same whether it is requested alone or with its batch mate.
    const int batch = params.gen3c_batch;
    const int batch_first = (first / batch) * batch;
    const int batch_end = std::min(total, ((first + count - 1) / batch + 1) * batch);
    std::vector<float> max_depth(static_cast<std::size_t>(batch_end - batch_first));
    pool_.parallelFor(batch_end - batch_first, [&](long long i, int) {
      max_depth[static_cast<std::size_t>(i)] =
          maxTargetDepth(cloud, trajectory.cameras[static_cast<std::size_t>(batch_first + i)]);
    });
    max_log_depth.resize(static_cast<std::size_t>(count));
    for (int f = first; f < first + count; ++f) {
      const int b0 = (f / batch) * batch;
      float m = -std::numeric_limits<float>::infinity();
      for (int g = b0; g < std::min(total, b0 + batch); ++g) {
        m = std::max(m, max_depth[static_cast<std::size_t>(g - batch_first)]);
      }
      // GEN3C saturates depth at [0, 1000] before the logarithm.
      max_log_depth[static_cast<std::size_t>(f - first)] = std::log1p(std::min(std::max(m, 0.0f), 1000.0f));
    }
  }

  pool_.parallelFor(count, [&](long long i, int worker) {
    const TargetCamera& camera = trajectory.cameras[static_cast<std::size_t>(first + i)];
    RenderedFrame& out = frames[static_cast<std::size_t>(i)];
    if (params.mode == SplatMode::kZbuffer) {
      renderZbuffer(cloud, camera, trajectory.size, params, worker, out);
    } else {
      renderGen3c(cloud, camera, trajectory.size, params, max_log_depth[static_cast<std::size_t>(i)],
                  worker, out);
    }
  });
}

void PointSplatter::renderZbuffer(const ColoredCloud& cloud, const TargetCamera& camera,
                                  ImageSize size, const SplatParams& params, int worker,
                                  RenderedFrame& out) {
  const int width = size.width, height = size.height;
  std::vector<std::uint64_t>& keys = depth_keys_[static_cast<std::size_t>(worker)];
  keys.assign(static_cast<std::size_t>(size.pixels()), kEmptyKey);
  std::uint64_t* key = keys.data();

  const ViewTransform v(camera);
  // One source pixel at depth z_src spans f_target / f_source * z_src / z_target target pixels.
  const float spread =
      params.grow_footprint
          ? static_cast<float>(std::max(camera.intrinsics.fx / cloud.intrinsics.fx,
                                        camera.intrinsics.fy / cloud.intrinsics.fy))
          : 0.0f;
  const int max_fp = params.max_footprint;
  const float u_hi = width - 0.5f, v_hi = height - 0.5f;
  const std::size_t n = cloud.size();
  const float* px = cloud.x.data();
  const float* py = cloud.y.data();
  const float* pz = cloud.z.data();

  for (std::size_t i = 0; i < n; ++i) {
    const float x = px[i], y = py[i], z = pz[i];
    const float zc = v.r[6] * x + v.r[7] * y + v.r[8] * z + v.t[2];
    if (!(zc > 0.0f)) continue;
    const float inv = 1.0f / zc;
    const float u = v.fx * (v.r[0] * x + v.r[1] * y + v.r[2] * z + v.t[0]) * inv + v.cx;
    const float w = v.fy * (v.r[3] * x + v.r[4] * y + v.r[5] * z + v.t[1]) * inv + v.cy;
    // Positive floats order like their bit patterns: the high word makes the nearest point win,
    // the low word (the point index) breaks ties deterministically and names the colour.
    const std::uint64_t k = static_cast<std::uint64_t>(floatBits(zc)) << 32 | i;
    const float magnification = spread * z * inv;
    if (magnification <= 1.0f) {
      if (!(u >= -0.5f && u < u_hi && w >= -0.5f && w < v_hi)) continue;
      const std::size_t p = static_cast<std::size_t>(static_cast<int>(w + 0.5f)) * width +
                            static_cast<int>(u + 0.5f);
      if (k < key[p]) key[p] = k;
      continue;
    }
    // Footprint of fp x fp pixels centred on the point: for odd fp the pixel it rounds to plus
    // (fp - 1) / 2 on each side, for even fp the fp / 2 pixels nearest on each side.
    const int fp = std::min(max_fp, static_cast<int>(std::ceil(magnification)));
    const float offset = 1.0f - 0.5f * fp;
    if (!(u + offset > -1e6f && u + offset < 1e6f && w + offset > -1e6f && w + offset < 1e6f)) continue;
    const int u0 = static_cast<int>(std::floor(u + offset));
    const int v0 = static_cast<int>(std::floor(w + offset));
    const int ua = std::max(0, u0), ub = std::min(width, u0 + fp);
    const int va = std::max(0, v0), vb = std::min(height, v0 + fp);
    for (int r = va; r < vb; ++r) {
      std::uint64_t* row = key + static_cast<std::size_t>(r) * width;
      for (int c = ua; c < ub; ++c) {
        if (k < row[c]) row[c] = k;
      }
    }
  }

  allocate(out, size, false);
  const std::uint32_t* colours = cloud.bgr.data();
  for (int r = 0; r < height; ++r) {
    const std::uint64_t* row = key + static_cast<std::size_t>(r) * width;
    cv::Vec3b* bgr = out.bgr.ptr<cv::Vec3b>(r);
    std::uint8_t* mask = out.mask.ptr<std::uint8_t>(r);
    float* depth = out.depth.ptr<float>(r);
    for (int c = 0; c < width; ++c) {
      if (row[c] == kEmptyKey) {
        bgr[c] = cv::Vec3b(0, 0, 0);
        mask[c] = 0;
        depth[c] = 0.0f;
        continue;
      }
      const std::uint32_t colour = colours[row[c] & 0xffffffffu];
      bgr[c] = cv::Vec3b(colour & 0xff, (colour >> 8) & 0xff, (colour >> 16) & 0xff);
      mask[c] = 255;
      depth[c] = bitsToFloat(static_cast<std::uint32_t>(row[c] >> 32));
    }
  }
}

void PointSplatter::renderGen3c(const ColoredCloud& cloud, const TargetCamera& camera,
                                ImageSize size, const SplatParams& params, float max_log_depth,
                                int worker, RenderedFrame& out) {
  const int width = size.width, height = size.height;
  // Per pixel: weighted sums of b, g, r, depth, and the weight itself.
  constexpr int kSums = 5;
  std::vector<float>& acc = accumulators_[static_cast<std::size_t>(worker)];
  acc.assign(static_cast<std::size_t>(size.pixels()) * kSums, 0.0f);
  float* sums = acc.data();

  // Colours in [-1, 1] as GEN3C normalises images: c / 127.5 - 1.
  float signed_value[256];
  for (int c = 0; c < 256; ++c) signed_value[c] = static_cast<float>(c) / 127.5f - 1.0f;

  const ViewTransform v(camera);
  const float exponent_scale = max_log_depth > 0.0f ? params.gen3c_sharpness / max_log_depth : 0.0f;
  // GEN3C splats into an image with a 1-pixel border (positions shifted by +1 and clamped to
  // [0, W+1] x [0, H+1]) and crops the border afterwards: border indices are simply skipped here.
  const float ox_max = static_cast<float>(width + 1), oy_max = static_cast<float>(height + 1);
  const std::size_t n = cloud.size();
  const float* px = cloud.x.data();
  const float* py = cloud.y.data();
  const float* pz = cloud.z.data();
  const std::uint32_t* colours = cloud.bgr.data();

  for (std::size_t i = 0; i < n; ++i) {
    const float x = px[i], y = py[i], z = pz[i];
    const float zc = v.r[6] * x + v.r[7] * y + v.r[8] * z + v.t[2];
    if (!(zc > 0.0f)) continue;
    const float inv = 1.0f / zc;
    const float u = v.fx * (v.r[0] * x + v.r[1] * y + v.r[2] * z + v.t[0]) * inv + v.cx;
    const float w = v.fy * (v.r[3] * x + v.r[4] * y + v.r[5] * z + v.t[1]) * inv + v.cy;
    const float ox = std::min(std::max(u + 1.0f, 0.0f), ox_max);
    const float oy = std::min(std::max(w + 1.0f, 0.0f), oy_max);
    const float x0 = std::floor(ox), x1 = std::ceil(ox);
    const float y0 = std::floor(oy), y1 = std::ceil(oy);
    const int ix0 = static_cast<int>(x0), ix1 = static_cast<int>(x1);
    const int iy0 = static_cast<int>(y0), iy1 = static_cast<int>(y1);
    // Entirely in the border (off-image point): nothing survives the crop.
    if (ix1 < 1 || ix0 > width || iy1 < 1 || iy0 > height) continue;
    // Bilinear weights exactly as GEN3C forms them, including the integer-position case where
    // floor == ceil and all four taps hit the same pixel with weight 1 each.
    const float wx0 = 1.0f - (ox - x0), wx1 = 1.0f - (x1 - ox);
    const float wy0 = 1.0f - (oy - y0), wy1 = 1.0f - (y1 - oy);
    const float soft_z = std::exp(std::log1p(std::min(zc, 1000.0f)) * exponent_scale) + 1e-7f;
    const std::uint32_t colour = colours[i];
    const float b = signed_value[colour & 0xff];
    const float g = signed_value[(colour >> 8) & 0xff];
    const float r = signed_value[(colour >> 16) & 0xff];
    const int tap_x[2] = {ix0, ix1}, tap_y[2] = {iy0, iy1};
    const float weight_x[2] = {wx0, wx1}, weight_y[2] = {wy0, wy1};
    for (int a = 0; a < 2; ++a) {
      const int ty = tap_y[a];
      if (ty < 1 || ty > height) continue;
      for (int c = 0; c < 2; ++c) {
        const int tx = tap_x[c];
        if (tx < 1 || tx > width) continue;
        const float weight = weight_y[a] * weight_x[c] / soft_z;
        float* s = sums + (static_cast<std::size_t>(ty - 1) * width + (tx - 1)) * kSums;
        s[0] += weight * b;
        s[1] += weight * g;
        s[2] += weight * r;
        s[3] += weight * zc;
        s[4] += weight;
      }
    }
  }

  allocate(out, size, true);
  for (int row = 0; row < height; ++row) {
    const float* s = sums + static_cast<std::size_t>(row) * width * kSums;
    cv::Vec3b* bgr = out.bgr.ptr<cv::Vec3b>(row);
    cv::Vec3f* signed_bgr = out.signed_bgr.ptr<cv::Vec3f>(row);
    std::uint8_t* mask = out.mask.ptr<std::uint8_t>(row);
    float* depth = out.depth.ptr<float>(row);
    for (int c = 0; c < width; ++c, s += kSums) {
      if (!(s[4] > 0.0f)) {
        bgr[c] = cv::Vec3b(0, 0, 0);
        signed_bgr[c] = cv::Vec3f(-1.0f, -1.0f, -1.0f);
        mask[c] = 0;
        depth[c] = 0.0f;
        continue;
      }
      for (int ch = 0; ch < 3; ++ch) {
        const float value = std::min(1.0f, std::max(-1.0f, s[ch] / s[4]));
        signed_bgr[c][ch] = value;
        bgr[c][ch] = static_cast<std::uint8_t>(std::lround((value + 1.0f) * 127.5f));
      }
      mask[c] = 255;
      depth[c] = s[3] / s[4];
    }
  }
}

}  // namespace multimodal_nvs
