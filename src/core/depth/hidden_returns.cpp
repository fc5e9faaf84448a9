#include "multimodal_nvs/core/depth/hidden_returns.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "multimodal_nvs/core/depth/angular_bins.hpp"

namespace multimodal_nvs {
namespace {

// The neighbouring scan line is searched up to this many typical scan-line spacings away: beyond
// it (a gap in the scan, the sky) a nearer return says nothing about what hides this one.
constexpr double kScanLineReach = 2.0;
// Half-width of a sample's image column, in along-line spacings.
constexpr double kColumnSpacings = 2.0;
// A sample's own scan line: its neighbours along the line lie within this many spacings in
// elevation over one spacing along it (lines tilted by less than 14 degrees in the image).
constexpr double kOwnLine = 0.25;
// One sample in this many estimates the along-line spacing (a median: a subsample suffices).
constexpr std::size_t kSpacingSubsample = 16;
// Samples walked per column strip before giving up on a neighbour (a strip is one spacing wide,
// so the first sample past the line is almost always the one).
constexpr int kMaxWalk = 64;

/// Elevation (degrees, the camera's up) of the sample's point seen from `origin` (camera frame).
double elevationFrom(const Eigen::Vector3d& origin, const AngularSample& s) {
  constexpr double kDeg = M_PI / 180.0;
  const double az = s.azimuth_deg * kDeg, el = s.elevation_deg * kDeg;
  // az = atan2(x, z), el = atan2(-y, hypot(x, z)) (angular_samples.hpp), z = depth.
  const double z = s.depth, x = z * std::tan(az), y = -std::tan(el) * z / std::cos(az);
  const Eigen::Vector3d d = Eigen::Vector3d(x, y, z) - origin;
  return std::atan2(-d.y(), std::hypot(d.x(), d.z())) / kDeg;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

std::vector<AngularSample> dropReturnsHiddenFromCamera(const std::vector<AngularSample>& samples,
                                                       const PixelAngleGrid& angles,
                                                       double depth_ratio,
                                                       const Eigen::Vector3d& scan_origin,
                                                       std::size_t* dropped_count) {
  if (dropped_count != nullptr) *dropped_count = 0;
  std::vector<AngularSample> usable = usableSamples(samples);
  // The samples near the image (the triangulation's window).
  const AngularBox image = angles.extent();
  const float margin_az = std::max(2.0f, 0.1f * (image.az_max - image.az_min));
  const float margin_el = std::max(2.0f, 0.1f * (image.el_max - image.el_min));
  const float az_lo = image.az_min - margin_az, az_hi = image.az_max + margin_az;
  const float el_lo = image.el_min - margin_el, el_hi = image.el_max + margin_el;
  std::vector<AngularSample> near;
  std::vector<int> near_index;
  for (std::size_t i = 0; i < usable.size(); ++i) {
    const AngularSample& s = usable[i];
    if (s.azimuth_deg >= az_lo && s.azimuth_deg <= az_hi && s.elevation_deg >= el_lo &&
        s.elevation_deg <= el_hi) {
      near.push_back(s);
      near_index.push_back(static_cast<int>(i));
    }
  }
  if (near.size() < 3 * kSpacingSubsample) return usable;

  // Along-line spacing: the median distance to the nearest other sample.
  const double mean_spacing =
      std::sqrt((double(az_hi) - az_lo) * (double(el_hi) - el_lo) / double(near.size()));
  const AngularBins bins(near, std::max(1e-3, mean_spacing));
  std::vector<double> nearest_distance;
  std::vector<std::pair<double, int>> found;
  for (std::size_t i = 0; i < near.size(); i += kSpacingSubsample) {
    bins.nearest(near[i].azimuth_deg, near[i].elevation_deg, 3, found);
    for (const auto& f : found) {
      if (f.first > 0.0) {
        nearest_distance.push_back(std::sqrt(f.first));
        break;
      }
    }
  }
  const double along = median(std::move(nearest_distance));
  if (!(along > 0.0)) return usable;

  // Column strips one spacing wide, each sorted by elevation.
  const int strips = static_cast<int>(std::ceil((double(az_hi) - az_lo) / along)) + 1;
  std::vector<int> strip_of(near.size());
  for (std::size_t i = 0; i < near.size(); ++i) {
    strip_of[i] =
        std::clamp(static_cast<int>((double(near[i].azimuth_deg) - az_lo) / along), 0, strips - 1);
  }
  // Counting sort by strip, then each (short) strip by elevation.
  std::vector<int> strip_start(std::size_t(strips) + 1, 0);
  for (int t : strip_of)
    ++strip_start[t + 1];
  for (int t = 0; t < strips; ++t)
    strip_start[t + 1] += strip_start[t];
  std::vector<int> order(near.size());
  {
    std::vector<int> next(strip_start.begin(), strip_start.end() - 1);
    for (std::size_t i = 0; i < near.size(); ++i)
      order[next[strip_of[i]]++] = static_cast<int>(i);
  }
  for (int t = 0; t < strips; ++t) {
    std::sort(order.begin() + strip_start[t], order.begin() + strip_start[t + 1],
              [&](int a, int b) {
                if (near[a].elevation_deg != near[b].elevation_deg)
                  return near[a].elevation_deg < near[b].elevation_deg;
                return a < b;
              });
  }
  std::vector<float> sorted_el(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    sorted_el[k] = near[order[k]].elevation_deg;

  // The typical gap to the next scan line: the median, over a subsample, of the gap to the
  // nearest sample above in the sample's column past its own scan line (more than kOwnLine
  // spacings away in elevation).
  const float own_line = static_cast<float>(kOwnLine * along);
  std::vector<double> gaps;
  for (std::size_t i = 0; i < near.size(); i += kSpacingSubsample) {
    const AngularSample& s = near[i];
    float gap = std::numeric_limits<float>::infinity();
    for (int t = std::max(0, strip_of[i] - 1); t <= std::min(strips - 1, strip_of[i] + 1); ++t) {
      const auto first = sorted_el.begin() + strip_start[t];
      const auto last = sorted_el.begin() + strip_start[t + 1];
      auto it = std::upper_bound(first, last, s.elevation_deg + own_line);
      for (int walked = 0; it != last && walked < kMaxWalk; ++it, ++walked) {
        const AngularSample& o = near[order[it - sorted_el.begin()]];
        if (std::abs(o.azimuth_deg - s.azimuth_deg) > along) continue;
        gap = std::min(gap, o.elevation_deg - s.elevation_deg);
        break;
      }
    }
    if (std::isfinite(gap)) gaps.push_back(gap);
  }
  const float reach = static_cast<float>(kScanLineReach * median(std::move(gaps)));
  const float width = static_cast<float>(kColumnSpacings * along);
  const int strip_reach = static_cast<int>(std::ceil(kColumnSpacings));
  // A sample between two nearer returns of one surface in its column (the scan lines above and
  // below it in the image) is hidden when the scanner saw it outside that span: its ray passed
  // beside the surface, the camera's does not. Had the scanner's ray passed between them too, the
  // surface has a gap there (a railing, foliage) that the camera looks through as well.
  // Strip by strip, each strip's samples in rising elevation: the first sample of every
  // neighbouring strip past the own scan line above, and below, only moves up (cursors instead of
  // a binary search per sample and strip). The angles and depths in that order, contiguous.
  std::vector<float> sorted_az(order.size()), sorted_depth(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    sorted_az[k] = near[order[k]].azimuth_deg;
    sorted_depth[k] = near[order[k]].depth;
  }
  std::vector<std::uint8_t> hidden(usable.size(), 0);
  std::size_t dropped = 0;
  std::vector<int> up(2 * strip_reach + 1), down(2 * strip_reach + 1);
  for (int t = 0; t < strips; ++t) {
    const int u0 = std::max(0, t - strip_reach), u1 = std::min(strips - 1, t + strip_reach);
    for (int u = u0; u <= u1; ++u)
      up[u - u0] = down[u - u0] = strip_start[u];
    for (int k = strip_start[t]; k < strip_start[t + 1]; ++k) {
      const float el = sorted_el[k], az = sorted_az[k];
      const float limit = static_cast<float>(sorted_depth[k] / depth_ratio);
      // The nearest nearer return above and below, each on both sides of the sample's column
      // (so that the surface spans the sample: a return beside a near object's vertical edge has
      // the object on one side only); indices into the sorted arrays.
      int upper[2] = {-1, -1}, lower[2] = {-1, -1};  // left, right
      const auto consider = [&](int c, int(&pair)[2], bool rising) {
        const float d_az = sorted_az[c] - az;
        if (!(sorted_depth[c] < limit) || std::abs(d_az) > width) return;
        for (int side = 0; side < 2; ++side) {
          if (side == 0 ? d_az > 0.0f : d_az < 0.0f) continue;
          int& best = pair[side];
          if (best < 0 ||
              (rising ? sorted_el[c] < sorted_el[best] : sorted_el[c] > sorted_el[best]))
            best = c;
        }
      };
      for (int u = u0; u <= u1; ++u) {
        int& c = up[u - u0];
        while (c < strip_start[u + 1] && sorted_el[c] <= el + own_line)
          ++c;
        for (int j = c; j < strip_start[u + 1] && sorted_el[j] - el <= reach; ++j)
          consider(j, upper, true);
      }
      if (upper[0] < 0 || upper[1] < 0) continue;  // most samples: nothing nearer above
      for (int u = u0; u <= u1; ++u) {
        int& c = down[u - u0];
        while (c < strip_start[u + 1] && sorted_el[c] < el - own_line)
          ++c;
        for (int j = c - 1; j >= strip_start[u] && el - sorted_el[j] <= reach; --j)
          consider(j, lower, false);
      }
      if (lower[0] < 0 || lower[1] < 0) continue;
      const float upper_depth = std::min(sorted_depth[upper[0]], sorted_depth[upper[1]]);
      const float lower_depth = std::min(sorted_depth[lower[0]], sorted_depth[lower[1]]);
      if (std::max(upper_depth, lower_depth) > depth_ratio * std::min(upper_depth, lower_depth))
        continue;  // not one surface
      const auto from_scanner = [&](int c) { return elevationFrom(scan_origin, near[order[c]]); };
      const double seen = from_scanner(k);
      if (seen > std::max(from_scanner(upper[0]), from_scanner(upper[1])) ||
          seen < std::min(from_scanner(lower[0]), from_scanner(lower[1]))) {
        hidden[near_index[order[k]]] = 1;
        ++dropped;
      }
    }
  }
  if (dropped_count != nullptr) *dropped_count = dropped;
  if (dropped == 0) return usable;
  std::vector<AngularSample> visible;
  visible.reserve(usable.size() - dropped);
  for (std::size_t i = 0; i < usable.size(); ++i) {
    if (!hidden[i]) visible.push_back(usable[i]);
  }
  return visible;
}

}  // namespace multimodal_nvs
