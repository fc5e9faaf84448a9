#include "multimodal_nvs/core/render/splatting.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "multimodal_nvs/core/common/bit_cast.hpp"
#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

SplatMode parseSplatMode(const std::string& name) {
  if (name == "gen3c") return SplatMode::kGen3c;
  if (name == "zbuffer") return SplatMode::kZbuffer;
  throw InputError("unknown splat mode '" + name + "' (valid: gen3c, zbuffer)");
}

std::string toString(SplatMode mode) {
  return mode == SplatMode::kGen3c ? "gen3c" : "zbuffer";
}

namespace {

/// The rigid transform and intrinsics of one target view in float, as the inner loops use them.
struct ViewTransform {
  float r[9];
  float t[3];
  float fx, fy, cx, cy;

  explicit ViewTransform(const TargetCamera& camera) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        r[3 * i + j] = static_cast<float>(camera.world_to_camera(i, j));
      t[i] = static_cast<float>(camera.world_to_camera(i, 3));
    }
    fx = static_cast<float>(camera.intrinsics.fx);
    fy = static_cast<float>(camera.intrinsics.fy);
    cx = static_cast<float>(camera.intrinsics.cx);
    cy = static_cast<float>(camera.intrinsics.cy);
  }
};

constexpr std::uint64_t kEmptyKey = std::numeric_limits<std::uint64_t>::max();

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
                                                 const Trajectory& trajectory, int first, int count,
                                                 const SplatParams& params) {
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
      max_log_depth[static_cast<std::size_t>(f - first)] =
          std::log1p(std::min(std::max(m, 0.0f), 1000.0f));
    }
  }

  pool_.parallelFor(count, [&](long long i, int worker) {
    const TargetCamera& camera = trajectory.cameras[static_cast<std::size_t>(first + i)];
    RenderedFrame& out = frames[static_cast<std::size_t>(i)];
    if (params.mode == SplatMode::kZbuffer) {
      renderZbuffer(cloud, camera, trajectory.size, params, worker, out);
    } else {
      renderGen3c(cloud, camera, trajectory.size, params,
                  max_log_depth[static_cast<std::size_t>(i)], worker, out);
    }
  });
}

namespace {

/// Points are projected a block at a time in a branch-free loop the compiler vectorises; the
/// scatter into the image then runs over the block's results.
constexpr int kBlock = 1024;

/// Calls f(begin, m, x, y, z) for each run of at most kBlock points of the cloud: both splatting
/// loops project a block at once so that the projection vectorises.
template <class F>
void forEachPointBlock(const ColoredCloud& cloud, F&& f) {
  const std::size_t n = cloud.size();
  for (std::size_t begin = 0; begin < n; begin += kBlock) {
    const int m = static_cast<int>(std::min<std::size_t>(kBlock, n - begin));
    f(begin, m, cloud.x.data() + begin, cloud.y.data() + begin, cloud.z.data() + begin);
  }
}

struct ProjectedBlock {
  alignas(64) float u[kBlock];
  alignas(64) float v[kBlock];
  alignas(64) float z[kBlock];
  alignas(64) float extra[kBlock];  ///< zbuffer: magnification; gen3c: 1 / soft z-buffer weight
};

/// exp(y) for y in [0, 80] with ~1e-7 relative error, vectorisable (no libm call): the soft
/// z-buffer weight only sets relative weights, so this matches std::exp far below the rounding of
/// the float sums it feeds. (The exponent here is in [0, 50].)
inline float fastExp(float y) {
  const float n = static_cast<float>(static_cast<int>(y * 1.44269504088896341f + 0.5f));
  const float r = y - n * 0.693145751953125f - n * 1.42860682030941723212e-6f;
  float p = 1.0f / 5040.0f;
  p = p * r + 1.0f / 720.0f;
  p = p * r + 1.0f / 120.0f;
  p = p * r + 1.0f / 24.0f;
  p = p * r + 1.0f / 6.0f;
  p = p * r + 0.5f;
  p = p * r + 1.0f;
  p = p * r + 1.0f;
  const std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

/// log(x) for finite x > 0 with ~1e-7 relative error, vectorisable: x = 2^e m with m in
/// [sqrt(1/2), sqrt(2)), log m = 2 atanh(s), s = (m - 1) / (m + 1), |s| <= 0.172.
inline float fastLog(float x) {
  std::int32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  // Subtracting the bits of sqrt(1/2) puts the mantissa range at [sqrt(1/2), sqrt(2)).
  const std::int32_t offset = bits - 0x3f3504f3;
  const std::int32_t e = offset >> 23;
  const std::int32_t mbits = bits - (e << 23);
  float m;
  std::memcpy(&m, &mbits, sizeof m);
  const float s = (m - 1.0f) / (m + 1.0f);
  const float s2 = s * s;
  float p = 2.0f / 9.0f;
  p = p * s2 + 2.0f / 7.0f;
  p = p * s2 + 2.0f / 5.0f;
  p = p * s2 + 2.0f / 3.0f;
  p = p * s2 + 2.0f;
  return static_cast<float>(e) * 0.693147180559945309f + p * s;
}

constexpr std::int32_t kThousandBits = 0x447a0000;  // 1000.0f

/// GEN3C projection of one block: target position shifted by +1 into the bordered image, and the
/// inverse soft z-buffer weight. Arithmetic only, so that it vectorises; clamping and snapping
/// happen in the scatter loop.
void projectGen3cBlock(const ViewTransform& vt, const float* bx, const float* by, const float* bz,
                       int m, float exponent_scale, ProjectedBlock& block) {
  for (int j = 0; j < m; ++j) {
    const float x = bx[j], y = by[j], z = bz[j];
    const float zc = vt.r[6] * x + vt.r[7] * y + vt.r[8] * z + vt.t[2];
    const float inv = 1.0f / zc;  // points behind the camera (zc <= 0) are skipped when scattering
    block.u[j] = vt.fx * (vt.r[0] * x + vt.r[1] * y + vt.r[2] * z + vt.t[0]) * inv + vt.cx + 1.0f;
    block.v[j] = vt.fy * (vt.r[3] * x + vt.r[4] * y + vt.r[5] * z + vt.t[1]) * inv + vt.cy + 1.0f;
    block.z[j] = zc;
    // 1 / w = exp(sharpness log1p(z) / max log1p(z)) + 1e-7, with z saturated at 1000 (GEN3C
    // clamps to [0, 1000]; z <= 0 is skipped anyway). The saturation is an integer min on the
    // bit pattern, which orders like the value for positive floats: a float min here keeps GCC
    // from vectorising the loop.
    std::int32_t z_bits;
    std::memcpy(&z_bits, &zc, sizeof z_bits);
    z_bits = std::min(z_bits, kThousandBits);
    float sat;
    std::memcpy(&sat, &z_bits, sizeof sat);
    block.extra[j] = fastExp(fastLog(1.0f + sat) * exponent_scale) + 1e-7f;
  }
}

}  // namespace

void PointSplatter::renderZbuffer(const ColoredCloud& cloud, const TargetCamera& camera,
                                  ImageSize size, const SplatParams& params, int worker,
                                  RenderedFrame& out) {
  const int width = size.width, height = size.height;
  std::vector<std::uint64_t>& keys = depth_keys_[static_cast<std::size_t>(worker)];
  // The resolve pass below leaves the buffer empty again, so it is filled only when (re)sized.
  if (keys.size() != static_cast<std::size_t>(size.pixels())) {
    keys.assign(static_cast<std::size_t>(size.pixels()), kEmptyKey);
  }
  std::uint64_t* key = keys.data();

  const ViewTransform vt(camera);
  // One source pixel at depth z_src spans f_target / f_source * z_src / z_target target pixels.
  const float spread =
      params.grow_footprint
          ? static_cast<float>(std::max(camera.intrinsics.fx / cloud.intrinsics.fx,
                                        camera.intrinsics.fy / cloud.intrinsics.fy))
          : 0.0f;
  const int max_fp = params.max_footprint;
  const float u_hi = width - 0.5f, v_hi = height - 0.5f;
  const std::uint32_t* colours = cloud.bgr.data();
  ProjectedBlock block;

  forEachPointBlock(
      cloud, [&](std::size_t begin, int m, const float* bx, const float* by, const float* bz) {
        for (int j = 0; j < m; ++j) {
          const float x = bx[j], y = by[j], z = bz[j];
          const float zc = vt.r[6] * x + vt.r[7] * y + vt.r[8] * z + vt.t[2];
          const float inv = 1.0f / zc;
          block.u[j] = vt.fx * (vt.r[0] * x + vt.r[1] * y + vt.r[2] * z + vt.t[0]) * inv + vt.cx;
          block.v[j] = vt.fy * (vt.r[3] * x + vt.r[4] * y + vt.r[5] * z + vt.t[1]) * inv + vt.cy;
          block.z[j] = zc;
          block.extra[j] = spread * z * inv;
        }
        for (int j = 0; j < m; ++j) {
          const float zc = block.z[j], u = block.u[j], w = block.v[j];
          if (!(zc > 0.0f)) continue;
          // Positive floats order like their bit patterns: the high word makes the nearest point
          // win; the low word carries the colour, so the resolve pass never touches the cloud again
          // (equal depths fall to the smaller packed colour: deterministic).
          const std::uint64_t k =
              static_cast<std::uint64_t>(bitCast<std::uint32_t>(zc)) << 32 | colours[begin + j];
          const float magnification = block.extra[j];
          if (magnification <= 1.0f) {
            if (!(u >= -0.5f && u < u_hi && w >= -0.5f && w < v_hi)) continue;
            std::uint64_t& slot = key[static_cast<std::size_t>(static_cast<int>(w + 0.5f)) * width +
                                      static_cast<std::size_t>(static_cast<int>(u + 0.5f))];
            slot = std::min(slot, k);  // branch-free: which point wins is unpredictable
            continue;
          }
          // Footprint of fp x fp pixels centred on the point: for odd fp the pixel it rounds to
          // plus (fp - 1) / 2 on each side, for even fp the fp / 2 nearest pixels on each side.
          const int fp = std::min(max_fp, static_cast<int>(std::ceil(magnification)));
          const float offset = 1.0f - 0.5f * fp;
          const float ul = u + offset, vl = w + offset;
          if (!(ul > -static_cast<float>(fp) && ul < width && vl > -static_cast<float>(fp) &&
                vl < height)) {
            continue;
          }
          const int u0 = static_cast<int>(std::floor(ul));
          const int v0 = static_cast<int>(std::floor(vl));
          const int ua = std::max(0, u0), ub = std::min(width, u0 + fp);
          const int va = std::max(0, v0), vb = std::min(height, v0 + fp);
          for (int r = va; r < vb; ++r) {
            std::uint64_t* row = key + static_cast<std::size_t>(r) * width;
            for (int c = ua; c < ub; ++c)
              row[c] = std::min(row[c], k);
          }
        }
      });

  allocate(out, size, false);
  for (int r = 0; r < height; ++r) {
    std::uint64_t* row = key + static_cast<std::size_t>(r) * width;
    std::uint8_t* bgr = out.bgr.ptr<std::uint8_t>(r);
    std::uint8_t* mask = out.mask.ptr<std::uint8_t>(r);
    float* depth = out.depth.ptr<float>(r);
    for (int c = 0; c < width; ++c) {
      const std::uint64_t k = row[c];
      row[c] = kEmptyKey;
      const bool hit = k != kEmptyKey;
      bgr[3 * c] = hit ? static_cast<std::uint8_t>(k & 0xff) : 0;
      bgr[3 * c + 1] = hit ? static_cast<std::uint8_t>((k >> 8) & 0xff) : 0;
      bgr[3 * c + 2] = hit ? static_cast<std::uint8_t>((k >> 16) & 0xff) : 0;
      mask[c] = hit ? 255 : 0;
      depth[c] = hit ? bitCast<float>(static_cast<std::uint32_t>(k >> 32)) : 0.0f;
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
  for (int c = 0; c < 256; ++c)
    signed_value[c] = static_cast<float>(c) / 127.5f - 1.0f;

  const ViewTransform vt(camera);
  const float exponent_scale = max_log_depth > 0.0f ? params.gen3c_sharpness / max_log_depth : 0.0f;
  // GEN3C splats into an image with a 1-pixel border (positions shifted by +1 and clamped to
  // [0, W+1] x [0, H+1]) and crops the border afterwards: border taps are simply skipped here.
  const float ox_max = static_cast<float>(width + 1), oy_max = static_cast<float>(height + 1);
  const std::uint32_t* colours = cloud.bgr.data();
  ProjectedBlock block;

  forEachPointBlock(
      cloud, [&](std::size_t begin, int m, const float* bx, const float* by, const float* bz) {
        projectGen3cBlock(vt, bx, by, bz, m, exponent_scale, block);
        for (int j = 0; j < m; ++j) {
          const float zc = block.z[j];
          if (!(zc > 0.0f)) continue;
          float ox = std::min(std::max(block.u[j], 0.0f), ox_max);
          float oy = std::min(std::max(block.v[j], 0.0f), oy_max);
          // Round-off of unproject + project (~1e-4 px) must not split a point that lands on a
          // pixel centre: the soft weight can amplify a 1e-5 bilinear tap of a nearer point by
          // 1e10.
          const float rx = std::nearbyint(ox), ry = std::nearbyint(oy);
          if (std::abs(ox - rx) < 1e-3f) ox = rx;
          if (std::abs(oy - ry) < 1e-3f) oy = ry;
          const float x0 = std::floor(ox), x1 = std::ceil(ox);
          const float y0 = std::floor(oy), y1 = std::ceil(oy);
          const int ix0 = static_cast<int>(x0), ix1 = static_cast<int>(x1);
          const int iy0 = static_cast<int>(y0), iy1 = static_cast<int>(y1);
          if (ix1 < 1 || ix0 > width || iy1 < 1 || iy0 > height) continue;  // border only: cropped
          // Bilinear weights exactly as GEN3C forms them, including the integer-position case where
          // floor == ceil and all four taps hit the same pixel with weight 1 each.
          const float soft_z = block.extra[j];
          const float wx[2] = {1.0f - (ox - x0), 1.0f - (x1 - ox)};
          const float wy[2] = {1.0f - (oy - y0), 1.0f - (y1 - oy)};
          const int tx[2] = {ix0, ix1}, ty[2] = {iy0, iy1};
          const std::uint32_t colour = colours[begin + j];
          const float b = signed_value[colour & 0xff];
          const float g = signed_value[(colour >> 8) & 0xff];
          const float r = signed_value[(colour >> 16) & 0xff];
          for (int a = 0; a < 2; ++a) {
            if (ty[a] < 1 || ty[a] > height) continue;
            float* row = sums + static_cast<std::size_t>(ty[a] - 1) * width * kSums;
            for (int c = 0; c < 2; ++c) {
              if (tx[c] < 1 || tx[c] > width) continue;
              const float weight = wy[a] * wx[c] / soft_z;
              float* s = row + static_cast<std::size_t>(tx[c] - 1) * kSums;
              s[0] += weight * b;
              s[1] += weight * g;
              s[2] += weight * r;
              s[3] += weight * zc;
              s[4] += weight;
            }
          }
        }
      });

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
        bgr[c][ch] = static_cast<std::uint8_t>((value + 1.0f) * 127.5f + 0.5f);
      }
      mask[c] = 255;
      depth[c] = s[3] / s[4];
    }
  }
}

}  // namespace multimodal_nvs
