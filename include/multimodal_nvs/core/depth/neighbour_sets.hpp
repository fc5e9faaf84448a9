#pragma once
// The neighbour set of every output pixel: the samples within the angular radius.
#include <cstdint>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// A run of grid pixels in one row that all see the same neighbour set.
struct NeighbourSegment {
  int row;
  int col_begin;
  int col_end;  // exclusive
  int set_id;
};

/// The neighbourhoods of every grid pixel in the angular domain: all samples with
/// (d_az^2 + d_el^2) <= r^2, tested in float32 exactly as the reference does.
///
/// Along a row a pixel's neighbour set changes only where the row crosses a sample's circle, so
/// the row is stored as segments between crossings, and identical sets (which recur across rows
/// and within a row) are stored once. Everything that depends only on the set (length scale,
/// Cholesky factor, weights) is then computed once per set. Pixels in no segment have no neighbour.
class NeighbourSets {
 public:
  /// Members of a set, sorted by sample index.
  const int* members(int set_id) const { return members_.data() + offsets_[set_id]; }
  int setSize(int set_id) const { return offsets_[set_id + 1] - offsets_[set_id]; }
  int setCount() const { return static_cast<int>(offsets_.size()) - 1; }
  const std::vector<NeighbourSegment>& segments() const { return segments_; }
  /// Segments of `row` are segments()[rowBegin(row) .. rowBegin(row + 1)).
  std::size_t rowBegin(int row) const { return row_offsets_[row]; }
  long long pixelsWithNeighbours() const { return pixels_with_neighbours_; }

  static NeighbourSets build(const std::vector<AngularSample>& samples, const PixelAngleGrid& grid,
                             float radius_deg, ThreadPool& pool);

 private:
  std::vector<int> offsets_{0};
  std::vector<int> members_;
  std::vector<NeighbourSegment> segments_;
  std::vector<std::size_t> row_offsets_;
  long long pixels_with_neighbours_ = 0;
};

/// The exact neighbourhood predicate of the reference (float32 arithmetic, no contraction).
inline bool withinRadius(float az_pixel, float el_pixel, float az_sample, float el_sample,
                         float radius_sq) {
  const float da = az_pixel - az_sample;
  const float de = el_pixel - el_sample;
  const float da2 = da * da;
  const float de2 = de * de;
  return da2 + de2 <= radius_sq;
}

}  // namespace multimodal_nvs
