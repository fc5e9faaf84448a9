// The approximation for dense input (max_neighbors > 0). With LiDAR a 2 deg circle holds ~200
// samples and neighbour sets almost never repeat, so the exact method needs one O(n^3) length-scale
// search per pixel. Here every tile of approx_tile x approx_tile grid pixels shares one set (the
// max_neighbors samples nearest to the tile centre, among those that can reach the tile) and one
// length scale. A pixel with no sample of that set within the radius gets the prior, as in the
// exact method.
#include <algorithm>
#include <cmath>

#include "multimodal_nvs/core/depth_models.hpp"
#include "multimodal_nvs/core/local_gp.hpp"

namespace multimodal_nvs {
namespace {

/// Uniform bins over the samples' angular bounding box, for radius queries around tile centres.
class AngularBins {
 public:
  AngularBins(const std::vector<AngularSample>& samples, double bin_deg) : bin_(bin_deg) {
    if (samples.empty()) return;
    min_az_ = max_az_ = samples[0].azimuth_deg;
    min_el_ = max_el_ = samples[0].elevation_deg;
    for (const auto& s : samples) {
      min_az_ = std::min<double>(min_az_, s.azimuth_deg);
      max_az_ = std::max<double>(max_az_, s.azimuth_deg);
      min_el_ = std::min<double>(min_el_, s.elevation_deg);
      max_el_ = std::max<double>(max_el_, s.elevation_deg);
    }
    nx_ = static_cast<int>((max_az_ - min_az_) / bin_) + 1;
    ny_ = static_cast<int>((max_el_ - min_el_) / bin_) + 1;
    start_.assign(std::size_t(nx_) * ny_ + 1, 0);
    for (const auto& s : samples) ++start_[binOf(s) + 1];
    for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    order_.resize(samples.size());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < samples.size(); ++i) order_[fill[binOf(samples[i])]++] = int(i);
  }

  template <typename Visit>
  void query(double az, double el, double reach, Visit&& visit) const {
    if (order_.empty()) return;
    const int x0 = std::max(0, static_cast<int>(std::floor((az - reach - min_az_) / bin_)));
    const int x1 = std::min(nx_ - 1, static_cast<int>(std::floor((az + reach - min_az_) / bin_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((el - reach - min_el_) / bin_)));
    const int y1 = std::min(ny_ - 1, static_cast<int>(std::floor((el + reach - min_el_) / bin_)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t b = std::size_t(y) * nx_ + x;
        for (int k = start_[b]; k < start_[b + 1]; ++k) visit(order_[k]);
      }
    }
  }

 private:
  std::size_t binOf(const AngularSample& s) const {
    const int x = std::min(nx_ - 1, static_cast<int>((s.azimuth_deg - min_az_) / bin_));
    const int y = std::min(ny_ - 1, static_cast<int>((s.elevation_deg - min_el_) / bin_));
    return std::size_t(y) * nx_ + x;
  }

  double bin_;
  double min_az_ = 0, max_az_ = 0, min_el_ = 0, max_el_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_;
  std::vector<int> order_;
};

struct TileWorkspace {
  explicit TileWorkspace(const LocalGpParams& p) : gp(p) {}
  LocalGp gp;
  std::vector<std::pair<double, int>> candidates;
  std::vector<int> members;
  std::vector<float> az, el;
  std::vector<double> y, factor, beta;
  std::vector<float> mean, var;
};

}  // namespace

int predictTiledLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, double shift, ThreadPool& pool,
                        PixelPredictions& out) {
  const LocalGpParams& gp = params.gp;
  const std::size_t total = static_cast<std::size_t>(angles.grid().size());
  out.mean.assign(total, static_cast<float>(shift));
  out.variance.assign(total, static_cast<float>(gp.priorVariance()));
  if (samples.empty()) return 0;
  const std::vector<double> targets = shiftedTargets(samples, shift);
  const AngularBins bins(samples, params.radius_deg);

  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  const int tile = params.approx_tile;
  const int tiles_x = (cols + tile - 1) / tile, tiles_y = (rows + tile - 1) / tile;
  const float radius_sq = static_cast<float>(params.radius_deg * params.radius_deg);
  std::vector<TileWorkspace> workspaces(pool.size(), TileWorkspace(gp));
  std::vector<std::uint8_t> solved(std::size_t(tiles_x) * tiles_y, 0);

  pool.parallelFor(static_cast<long long>(tiles_x) * tiles_y, [&](long long t, int worker) {
    TileWorkspace& ws = workspaces[worker];
    const int r0 = static_cast<int>(t / tiles_x) * tile, c0 = static_cast<int>(t % tiles_x) * tile;
    const int r1 = std::min(rows, r0 + tile), c1 = std::min(cols, c0 + tile);
    const int rc = (r0 + r1 - 1) / 2, cc = (c0 + c1 - 1) / 2;
    const double az_c = angles.azimuthRow(rc)[cc], el_c = angles.elevationRow(rc)[cc];
    double half_diagonal = 0.0;
    for (int r : {r0, r1 - 1}) {
      for (int c : {c0, c1 - 1}) {
        half_diagonal = std::max(half_diagonal, std::hypot(angles.azimuthRow(r)[c] - az_c,
                                                           angles.elevationRow(r)[c] - el_c));
      }
    }
    const double reach = params.radius_deg + half_diagonal;
    ws.candidates.clear();
    bins.query(az_c, el_c, reach, [&](int i) {
      const double da = samples[i].azimuth_deg - az_c, de = samples[i].elevation_deg - el_c;
      const double d2 = da * da + de * de;
      if (d2 <= reach * reach) ws.candidates.emplace_back(d2, i);
    });
    if (ws.candidates.empty()) return;
    const std::size_t keep =
        std::min<std::size_t>(ws.candidates.size(), static_cast<std::size_t>(params.max_neighbors));
    std::nth_element(ws.candidates.begin(), ws.candidates.begin() + (keep - 1),
                     ws.candidates.end());
    ws.members.clear();
    for (std::size_t k = 0; k < keep; ++k) ws.members.push_back(ws.candidates[k].second);
    std::sort(ws.members.begin(), ws.members.end());
    const int n = static_cast<int>(keep);
    ws.az.resize(n);
    ws.el.resize(n);
    ws.y.resize(n);
    for (int i = 0; i < n; ++i) {
      ws.az[i] = samples[ws.members[i]].azimuth_deg;
      ws.el[i] = samples[ws.members[i]].elevation_deg;
      ws.y[i] = targets[ws.members[i]];
    }
    ws.gp.setData(ws.az.data(), ws.el.data(), ws.y.data(), n);
    const double length_scale = ws.gp.searchLengthScale();
    if (!ws.gp.posterior(length_scale, ws.factor, ws.beta)) return;
    solved[t] = 1;
    const int width = c1 - c0;
    ws.mean.resize(width);
    ws.var.resize(width);
    for (int r = r0; r < r1; ++r) {
      const float* az = angles.azimuthRow(r) + c0;
      const float* el = angles.elevationRow(r) + c0;
      predictFromFactor(ws.factor.data(), ws.beta.data(), ws.az.data(), ws.el.data(), n,
                        length_scale, gp, az, el, width, shift, ws.mean.data(), ws.var.data());
      const std::size_t row_start = std::size_t(r) * cols + c0;
      for (int p = 0; p < width; ++p) {
        bool supported = false;
        for (int i = 0; i < n && !supported; ++i) {
          supported = withinRadius(az[p], el[p], ws.az[i], ws.el[i], radius_sq);
        }
        if (!supported) continue;  // no sample within the radius: prior, as in the exact method
        out.mean[row_start + p] = ws.mean[p];
        out.variance[row_start + p] = ws.var[p];
      }
    }
  });
  int count = 0;
  for (auto s : solved) count += s;
  return count;
}

}  // namespace multimodal_nvs
