#include "multimodal_nvs/core/neighbour_sets.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <unordered_map>

namespace multimodal_nvs {
namespace {

// Margin (degrees) added to every analytic bound before the exact float32 test decides. Far larger
// than float32 rounding of angles (< 1e-5 deg), so no member is ever missed.
constexpr float kSearchMarginDeg = 1e-3f;

// Sets found by one worker, deduplicated by a Zobrist hash (XOR of one random word per member,
// updated in O(1) per circle crossing) and confirmed by comparing members.
struct LocalSetTable {
  std::unordered_multimap<std::uint64_t, int> by_hash;
  std::vector<int> offsets{0};
  std::vector<int> members;

  int intern(std::uint64_t hash, const std::vector<int>& set) {
    auto range = by_hash.equal_range(hash);
    for (auto it = range.first; it != range.second; ++it) {
      const int id = it->second;
      const int size = offsets[id + 1] - offsets[id];
      if (size == static_cast<int>(set.size()) &&
          std::equal(set.begin(), set.end(), members.begin() + offsets[id])) {
        return id;
      }
    }
    const int id = static_cast<int>(offsets.size()) - 1;
    members.insert(members.end(), set.begin(), set.end());
    offsets.push_back(static_cast<int>(members.size()));
    by_hash.emplace(hash, id);
    return id;
  }
};

// Separate function with restrict pointers: without them the byte stores may alias the float
// loads and GCC keeps the loop scalar (measured 3x slower).
void markWithinRadius(const float* __restrict az, const float* __restrict el, int count, float saz,
                      float sel, float radius_sq, std::uint8_t* __restrict inside) {
  for (int c = 0; c < count; ++c) inside[c] = withinRadius(az[c], el[c], saz, sel, radius_sq);
}

struct RowScratch {
  std::vector<std::pair<int, int>> crossings;  // (column, sample) where membership toggles
  std::vector<int> current;                    // sorted members at the sweep position
  std::vector<std::uint8_t> inside;            // membership over one sample's column window
};

struct RowResult {
  std::vector<NeighbourSegment> segments;  // set_id refers to the worker's LocalSetTable
  std::vector<std::uint64_t> hashes;
  int worker = 0;
};

}  // namespace

NeighbourSets NeighbourSets::build(const std::vector<AngularSample>& samples,
                                   const PixelAngleGrid& grid, float radius_deg,
                                   ThreadPool& pool) {
  const int rows = grid.grid().rows();
  const int cols = grid.grid().cols();
  const float radius_sq = radius_deg * radius_deg;
  const float reach = radius_deg + kSearchMarginDeg;

  // Samples sorted by elevation, so that each row finds its candidates by binary search.
  std::vector<int> by_elevation(samples.size());
  std::iota(by_elevation.begin(), by_elevation.end(), 0);
  std::sort(by_elevation.begin(), by_elevation.end(), [&](int a, int b) {
    return samples[a].elevation_deg < samples[b].elevation_deg ||
           (samples[a].elevation_deg == samples[b].elevation_deg && a < b);
  });
  std::vector<float> sorted_elevation(samples.size());
  for (std::size_t i = 0; i < by_elevation.size(); ++i) {
    sorted_elevation[i] = samples[by_elevation[i]].elevation_deg;
  }
  std::vector<std::uint64_t> zobrist(samples.size());
  std::mt19937_64 rng(0x6d6d6e7673ULL);
  for (auto& z : zobrist) z = rng();

  std::vector<LocalSetTable> tables(pool.size());
  std::vector<RowScratch> scratch(pool.size());
  std::vector<RowResult> row_results(rows);

  pool.parallelFor(rows, [&](long long row_index, int worker) {
    const int row = static_cast<int>(row_index);
    RowScratch& s = scratch[worker];
    RowResult& result = row_results[row];
    result.worker = worker;
    s.crossings.clear();
    const float* az = grid.azimuthRow(row);
    const float* el = grid.elevationRow(row);
    const auto first = std::lower_bound(sorted_elevation.begin(), sorted_elevation.end(),
                                        grid.minElevation(row) - reach);
    const auto last = std::upper_bound(first, sorted_elevation.end(),
                                       grid.maxElevation(row) + reach);
    for (auto it = first; it != last; ++it) {
      const int sample = by_elevation[it - sorted_elevation.begin()];
      const float saz = samples[sample].azimuth_deg;
      const float sel = samples[sample].elevation_deg;
      // Azimuth grows along a row; one column of slack covers float32 non-monotonicity.
      int c0 = static_cast<int>(std::lower_bound(az, az + cols, saz - reach) - az) - 1;
      int c1 = static_cast<int>(std::upper_bound(az, az + cols, saz + reach) - az) + 1;
      c0 = std::max(c0, 0);
      c1 = std::min(c1, cols);
      // The exact test over the window in a branch-free (vectorised) loop, then the toggles.
      if (c1 <= c0) continue;
      s.inside.resize(c1 - c0 + 1);
      std::uint8_t* inside = s.inside.data();
      markWithinRadius(az + c0, el + c0, c1 - c0, saz, sel, radius_sq, inside);
      inside[c1 - c0] = 0;  // sentinel: every run ends inside the buffer
      const std::uint8_t* p = inside;
      const std::uint8_t* end = inside + (c1 - c0);
      while ((p = static_cast<const std::uint8_t*>(std::memchr(p, 1, end - p))) != nullptr) {
        const std::uint8_t* q = static_cast<const std::uint8_t*>(std::memchr(p, 0, end + 1 - p));
        s.crossings.emplace_back(c0 + static_cast<int>(p - inside), sample);
        s.crossings.emplace_back(c0 + static_cast<int>(q - inside), sample);
        if (q >= end) break;
        p = q;
      }
    }
    if (s.crossings.empty()) return;
    std::sort(s.crossings.begin(), s.crossings.end());

    s.current.clear();
    std::uint64_t hash = 0;
    int position = 0;
    std::size_t i = 0;
    while (i < s.crossings.size()) {
      const int column = s.crossings[i].first;
      if (column > position && !s.current.empty()) {
        const int id = tables[worker].intern(hash, s.current);
        result.segments.push_back({row, position, column, id});
      }
      for (; i < s.crossings.size() && s.crossings[i].first == column; ++i) {
        const int sample = s.crossings[i].second;
        auto pos = std::lower_bound(s.current.begin(), s.current.end(), sample);
        if (pos != s.current.end() && *pos == sample) {
          s.current.erase(pos);
        } else {
          s.current.insert(pos, sample);
        }
        hash ^= zobrist[sample];
      }
      position = column;
    }
  });

  // Merge the per-worker tables into one; which worker found a set first does not matter, since
  // everything computed from a set depends only on its (sorted) members.
  NeighbourSets out;
  std::vector<std::vector<int>> global_id(tables.size());
  {
    LocalSetTable merged;
    std::vector<int> set;
    for (std::size_t w = 0; w < tables.size(); ++w) {
      const LocalSetTable& t = tables[w];
      global_id[w].resize(t.offsets.size() - 1);
      for (std::size_t id = 0; id + 1 < t.offsets.size(); ++id) {
        set.assign(t.members.begin() + t.offsets[id], t.members.begin() + t.offsets[id + 1]);
        std::uint64_t hash = 0;
        for (int m : set) hash ^= zobrist[m];
        global_id[w][id] = merged.intern(hash, set);
      }
    }
    out.offsets_ = std::move(merged.offsets);
    out.members_ = std::move(merged.members);
  }
  out.row_offsets_.assign(rows + 1, 0);
  std::size_t total = 0;
  for (int r = 0; r < rows; ++r) total += row_results[r].segments.size();
  out.segments_.reserve(total);
  for (int r = 0; r < rows; ++r) {
    out.row_offsets_[r] = out.segments_.size();
    for (NeighbourSegment seg : row_results[r].segments) {
      seg.set_id = global_id[row_results[r].worker][seg.set_id];
      out.pixels_with_neighbours_ += seg.col_end - seg.col_begin;
      out.segments_.push_back(seg);
    }
  }
  out.row_offsets_[rows] = out.segments_.size();
  return out;
}

}  // namespace multimodal_nvs
