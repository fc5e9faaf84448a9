#include "multimodal_nvs/core/depth/neighbour_sets.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <unordered_map>

#include "multimodal_nvs/core/common/per_worker.hpp"

namespace multimodal_nvs {
namespace {

// Margin (degrees) added to every analytic bound before the exact float32 test decides. Far larger
// than float32 rounding of angles (< 1e-5 deg), so no member is ever missed.
constexpr float kSearchMarginDeg = 1e-3f;

// Sets found by one worker, deduplicated by a Zobrist hash (XOR of one random word per member,
// updated in O(1) per circle crossing) and confirmed by comparing members. An open-addressing table
// (linear probing, at most half full): std::unordered_multimap's node allocations were most of the
// interning time.
class LocalSetTable {
 public:
  std::vector<int> offsets{0};
  std::vector<int> members;

  int intern(std::uint64_t hash, const int* set, int size) {
    if (2 * (count_ + 1) > slot_id_.size()) grow();
    std::size_t slot = hash & mask_;
    for (; slot_id_[slot] >= 0; slot = (slot + 1) & mask_) {
      const int id = slot_id_[slot];
      if (slot_hash_[slot] == hash && offsets[id + 1] - offsets[id] == size &&
          std::equal(set, set + size, members.begin() + offsets[id])) {
        return id;
      }
    }
    const int id = static_cast<int>(offsets.size()) - 1;
    members.insert(members.end(), set, set + size);
    offsets.push_back(static_cast<int>(members.size()));
    slot_hash_[slot] = hash;
    slot_id_[slot] = id;
    ++count_;
    return id;
  }

 private:
  void grow() {
    const std::size_t capacity = std::max<std::size_t>(1024, 2 * slot_id_.size());
    std::vector<std::uint64_t> old_hash(capacity, 0);
    std::vector<int> old_id(capacity, -1);
    old_hash.swap(slot_hash_);
    old_id.swap(slot_id_);
    mask_ = capacity - 1;
    for (std::size_t i = 0; i < old_id.size(); ++i) {
      if (old_id[i] < 0) continue;
      std::size_t slot = old_hash[i] & mask_;
      while (slot_id_[slot] >= 0)
        slot = (slot + 1) & mask_;
      slot_hash_[slot] = old_hash[i];
      slot_id_[slot] = old_id[i];
    }
  }

  std::vector<std::uint64_t> slot_hash_;
  std::vector<int> slot_id_;  // -1: empty
  std::size_t mask_ = 0;
  std::size_t count_ = 0;
};

// Separate function with restrict pointers: without them the byte stores may alias the float
// loads and GCC keeps the loop scalar (measured 3x slower). In blocks of 16 columns: a window is
// ~100 columns wide, and GCC's 64-wide vector loop left most of it to its scalar epilogue.
void markWithinRadius(const float* __restrict az, const float* __restrict el, int count, float saz,
                      float sel, float radius_sq, std::uint8_t* __restrict inside) {
  constexpr int kBlock = 16;
  int c = 0;
  for (; c + kBlock <= count; c += kBlock) {
    for (int k = 0; k < kBlock; ++k)
      inside[c + k] = withinRadius(az[c + k], el[c + k], saz, sel, radius_sq);
  }
  for (; c < count; ++c)
    inside[c] = withinRadius(az[c], el[c], saz, sel, radius_sq);
}

/// Eight 0/1 bytes (little-endian) as eight bits, byte i at bit i: each byte's bit lands at
/// 56 + i of the product and no two partial products meet, so nothing carries.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "packBytes reads bytes little-endian");
inline std::uint64_t packBytes(std::uint64_t bytes) {
  return (bytes * 0x0102040810204080ULL) >> 56;
}

/// Calls toggle(k) for every k in [0, count] where membership changes between k - 1 and k (before
/// the window and past its end count as outside): the starts and ends of the runs of 1s of
/// `inside`. Runs are found as the set bits of mask ^ (mask << 1), 64 columns per step (a memchr
/// per run start and end was a sixth of the sets' time). `inside` must hold count rounded up to 64
/// bytes, zero past count.
template <class Toggle>
void forEachToggle(const std::uint8_t* inside, int count, Toggle&& toggle) {
  std::uint64_t carry = 0;  // the previous word's last bit
  const int words = (count + 63) / 64;
  for (int w = 0; w < words; ++w) {
    std::uint64_t mask = 0;
    for (int b = 0; b < 8; ++b) {
      std::uint64_t bytes;
      std::memcpy(&bytes, inside + 64 * w + 8 * b, sizeof bytes);
      mask |= packBytes(bytes) << (8 * b);
    }
    for (std::uint64_t t = mask ^ ((mask << 1) | carry); t != 0; t &= t - 1)
      toggle(64 * w + __builtin_ctzll(t));
    carry = mask >> 63;
  }
  if (carry) toggle(64 * words);  // a run up to the end (count is then a multiple of 64)
}

// A crossing packed as column << 32 | sample, so that sorting compares one integer.
std::uint64_t packCrossing(int column, int sample) {
  return (static_cast<std::uint64_t>(column) << 32) | static_cast<std::uint32_t>(sample);
}
int crossingColumn(std::uint64_t crossing) {
  return static_cast<int>(crossing >> 32);
}
int crossingSample(std::uint64_t crossing) {
  return static_cast<int>(crossing & 0xffffffffu);
}

struct RowScratch {
  std::vector<std::uint64_t> crossings;  // where membership toggles, packed by packCrossing
  std::vector<int> current;              // sorted members at the sweep position
  std::vector<std::uint8_t> inside;      // membership over one sample's column window
};

// Where a row's segments went: the worker that found them appends every row's segments to one
// buffer of its own (set_id refers to that worker's LocalSetTable). A vector per row cost ~9 % of
// the sets' time in allocations.
struct RowSpan {
  int worker = 0;
  std::size_t begin = 0, end = 0;
};

}  // namespace

NeighbourSets NeighbourSets::build(const std::vector<AngularSample>& samples,
                                   const PixelAngleGrid& grid, float radius_deg, ThreadPool& pool) {
  const int rows = grid.grid().rows();
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
  // Every row's azimuth window of a sample is the same up to rounding: found once per sample.
  std::vector<std::pair<int, int>> column_window(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const float saz = samples[i].azimuth_deg;
    column_window[i] = grid.columnRange(saz - reach, saz + reach);
  }
  std::vector<std::uint64_t> zobrist(samples.size());
  std::mt19937_64 rng(0x6d6d6e7673ULL);
  for (auto& z : zobrist)
    z = rng();

  PerWorker<LocalSetTable> tables(pool.size());
  PerWorker<RowScratch> scratch(pool.size());
  PerWorker<std::vector<NeighbourSegment>> found(pool.size());
  std::vector<RowSpan> row_spans(rows);

  pool.parallelFor(rows, [&](long long row_index, int worker) {
    const int row = static_cast<int>(row_index);
    RowScratch& s = scratch[worker];
    std::vector<NeighbourSegment>& segments = found[worker];
    RowSpan& span = row_spans[row];
    span.worker = worker;
    span.begin = span.end = segments.size();
    s.crossings.clear();
    const float* az = grid.azimuthRow(row);
    const float* el = grid.elevationRow(row);
    const auto first = std::lower_bound(sorted_elevation.begin(), sorted_elevation.end(),
                                        grid.minElevation(row) - reach);
    const auto last =
        std::upper_bound(first, sorted_elevation.end(), grid.maxElevation(row) + reach);
    // The candidates come in elevation order, so their column windows jump about the row and each
    // first touch of a cache line of its angles stalled (the first load of the exact test was a
    // fifth of the build's samples). The row's span is fetched ahead instead.
    {
      int lo = grid.grid().cols(), hi = 0;
      for (auto it = first; it != last; ++it) {
        const int sample = by_elevation[it - sorted_elevation.begin()];
        lo = std::min(lo, column_window[sample].first);
        hi = std::max(hi, column_window[sample].second);
      }
      for (int c = lo; c < hi; c += 16) {
        __builtin_prefetch(az + c);
        __builtin_prefetch(el + c);
      }
    }
    for (auto it = first; it != last; ++it) {
      const int sample = by_elevation[it - sorted_elevation.begin()];
      const float saz = samples[sample].azimuth_deg;
      const float sel = samples[sample].elevation_deg;
      const int c0 = column_window[sample].first;
      const int c1 = column_window[sample].second;
      // The exact test over the window in a branch-free (vectorised) loop, then the toggles.
      if (c1 <= c0) continue;
      const int count = c1 - c0;
      s.inside.resize((count + 63) / 64 * 64);
      std::uint8_t* inside = s.inside.data();
      markWithinRadius(az + c0, el + c0, count, saz, sel, radius_sq, inside);
      std::fill(inside + count, inside + s.inside.size(), std::uint8_t{0});
      forEachToggle(inside, count,
                    [&](int k) { s.crossings.push_back(packCrossing(c0 + k, sample)); });
    }
    if (s.crossings.empty()) return;
    std::sort(s.crossings.begin(), s.crossings.end());

    s.current.clear();
    std::uint64_t hash = 0;
    int position = 0;
    std::size_t i = 0;
    while (i < s.crossings.size()) {
      const int column = crossingColumn(s.crossings[i]);
      if (column > position && !s.current.empty()) {
        const int id =
            tables[worker].intern(hash, s.current.data(), static_cast<int>(s.current.size()));
        segments.push_back({row, position, column, id});
      }
      for (; i < s.crossings.size() && crossingColumn(s.crossings[i]) == column; ++i) {
        const int sample = crossingSample(s.crossings[i]);
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
    span.end = segments.size();
  });

  // Merge the per-worker tables into one: worker 0's table is taken as it is (its ids stay), the
  // others' sets are interned into it. Which worker found a set first does not matter, since
  // everything computed from a set depends only on its (sorted) members.
  NeighbourSets out;
  std::vector<std::vector<int>> global_id(tables.size());  // worker 0: none, its ids stay
  {
    LocalSetTable merged = std::move(tables[0]);
    for (int w = 1; w < tables.size(); ++w) {
      const LocalSetTable& t = tables[w];
      global_id[w].resize(t.offsets.size() - 1);
      for (std::size_t id = 0; id + 1 < t.offsets.size(); ++id) {
        const int* set = t.members.data() + t.offsets[id];
        const int size = t.offsets[id + 1] - t.offsets[id];
        std::uint64_t hash = 0;
        for (int k = 0; k < size; ++k)
          hash ^= zobrist[set[k]];
        global_id[w][id] = merged.intern(hash, set, size);
      }
    }
    out.offsets_ = std::move(merged.offsets);
    out.members_ = std::move(merged.members);
  }
  // The rows' segments into one array, renumbered, in parallel (a serial copy was ~4 % of an exact
  // radar frame on two cores).
  out.row_offsets_.assign(rows + 1, 0);
  for (int r = 0; r < rows; ++r)
    out.row_offsets_[r + 1] = out.row_offsets_[r] + (row_spans[r].end - row_spans[r].begin);
  out.segments_.resize(out.row_offsets_[rows]);
  std::vector<long long> row_pixels(rows, 0);
  pool.parallelFor(
      rows,
      [&](long long r, int) {
        const RowSpan& span = row_spans[r];
        const int* renumber = span.worker == 0 ? nullptr : global_id[span.worker].data();
        const NeighbourSegment* in = found[span.worker].data();
        NeighbourSegment* out_segment = out.segments_.data() + out.row_offsets_[r];
        long long pixels = 0;
        for (std::size_t k = span.begin; k < span.end; ++k) {
          NeighbourSegment seg = in[k];
          if (renumber != nullptr) seg.set_id = renumber[seg.set_id];
          pixels += seg.col_end - seg.col_begin;
          *out_segment++ = seg;
        }
        row_pixels[r] = pixels;
      },
      16);
  for (int r = 0; r < rows; ++r)
    out.pixels_with_neighbours_ += row_pixels[r];
  return out;
}

}  // namespace multimodal_nvs
