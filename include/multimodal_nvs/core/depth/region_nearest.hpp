#pragma once
// k-nearest queries for many points of one small region (the pixels of an image tile), answered
// from the samples gathered once around it instead of a bin walk per query.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/depth/angular_bins.hpp"

namespace multimodal_nvs {

/// The samples that can be among the k nearest of any point of a region, and exact k-nearest
/// queries among them: a query's answer equals AngularBins::nearest() (squared distances computed
/// the same way, ties by index) for every point within the region's extent of its centre.
class RegionNearest {
 public:
  /// Gathers from `bins` every sample that can be among the k nearest of a point within `extent`
  /// (degrees) of (az, el), replacing the earlier region. By the triangle inequality a point p has
  /// its k nearest within kth(centre) + |p - centre|, so they lie within kth(centre) + 2 extent of
  /// the centre. `guess` (degrees, > 0) is a first bound on kth(centre), e.g. a neighbouring
  /// region's; a wrong guess costs a second gather or a larger first one, never a wrong answer.
  /// Returns kth(centre) (or the last bound tried when fewer than k samples exist).
  double gatherAround(const AngularBins& bins, double az, double el, double extent, std::size_t k,
                      double guess);

  /// Samples gathered.
  std::size_t size() const { return index_.size(); }

  /// The (at most) k gathered samples nearest to (az, el) as (squared distance, sample index),
  /// nearest first, ties by index. Cheapest when each query is near the previous one in the
  /// region (the order of the last answer is then nearly this one's).
  void nearest(double az, double el, std::size_t k, std::vector<std::pair<double, int>>& out);

 private:
  /// Gathers every sample within `radius` of (az, el), with its squared distance to that centre.
  void gather(const AngularBins& bins, double az, double el, double radius);
  /// Keeps the gathered samples at squared distance <= radius2 from the centre.
  void keepWithin(double radius2);

  std::vector<double> az_, el_;  // of the gathered samples (the bins' float angles, widened)
  std::vector<double> centre2_;  // squared distance to the region's centre
  std::vector<int> index_;
  std::vector<double> distance2_;  // of the current query, by gathered position
  std::vector<int> order_;         // its first head_: the last answer's positions, nearest first
  std::vector<int> passed_;        // positions that may enter the current answer
  std::vector<std::uint8_t> in_head_;  // by gathered position: in the first head_ of order_
  std::size_t head_ = 0;
};

}  // namespace multimodal_nvs
