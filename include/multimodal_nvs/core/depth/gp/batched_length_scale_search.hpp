#pragma once
// Runs the length-scale searches of many neighbour sets in SIMD batches of equal size.
#include <algorithm>
#include <vector>

#include "multimodal_nvs/core/common/per_worker.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"
#include "multimodal_nvs/core/depth/gp/length_scale_search.hpp"

namespace multimodal_nvs {

/// One set's samples as a search reads them.
struct SearchSet {
  int n = 0;
  const float* az = nullptr;
  const float* el = nullptr;
  const double* y = nullptr;
};

/// Searches the length scale of every set of 3..Search::kMaxBatchedSize samples, Search::kLanes
/// sets of one size at a time (a set's answer does not depend on its batch mates), writing
/// length_scales[s]. Returns the other sets, for the caller to search one by one.
/// `set(s)` gives set s as a SearchSet; `Search` is LengthScaleSearch or SingleLengthScaleSearch.
template <typename Search, typename SetAccess>
std::vector<int> searchInEqualSizeBatches(int set_count, const SetAccess& set,
                                          const LocalGpParams& gp, ThreadPool& pool,
                                          std::vector<double>& length_scales) {
  constexpr int kLanes = Search::kLanes;
  std::vector<std::vector<int>> by_size(Search::kMaxBatchedSize + 1);
  std::vector<int> others;
  for (int s = 0; s < set_count; ++s) {
    const int n = set(s).n;
    if (n >= 3 && n <= Search::kMaxBatchedSize) {
      by_size[n].push_back(s);
    } else {
      others.push_back(s);
    }
  }
  struct Batch {
    const int* sets;
    int count;
  };
  std::vector<Batch> batches;
  for (const std::vector<int>& equal_size : by_size) {
    for (std::size_t i = 0; i < equal_size.size(); i += kLanes) {
      batches.push_back({equal_size.data() + i,
                         static_cast<int>(std::min<std::size_t>(kLanes, equal_size.size() - i))});
    }
  }
  PerWorker<Search> searches(pool.size(), Search(gp));
  pool.parallelFor(static_cast<long long>(batches.size()), [&](long long b, int worker) {
    const Batch& batch = batches[b];
    const float* az[kLanes];
    const float* el[kLanes];
    const double* y[kLanes];
    double result[kLanes];
    for (int lane = 0; lane < batch.count; ++lane) {
      const SearchSet data = set(batch.sets[lane]);
      az[lane] = data.az;
      el[lane] = data.el;
      y[lane] = data.y;
    }
    searches[worker].search(set(batch.sets[0]).n, batch.count, az, el, y, result);
    for (int lane = 0; lane < batch.count; ++lane)
      length_scales[batch.sets[lane]] = result[lane];
  });
  return others;
}

/// The same with the search's precision chosen at run time: single (SingleLengthScaleSearch) for
/// models that keep no parity with the reference, double (LengthScaleSearch) otherwise.
template <typename SetAccess>
std::vector<int> searchInEqualSizeBatches(PredictionPrecision precision, int set_count,
                                          const SetAccess& set, const LocalGpParams& gp,
                                          ThreadPool& pool, std::vector<double>& length_scales) {
  if (precision == PredictionPrecision::kSingle) {
    return searchInEqualSizeBatches<SingleLengthScaleSearch>(set_count, set, gp, pool,
                                                             length_scales);
  }
  return searchInEqualSizeBatches<LengthScaleSearch>(set_count, set, gp, pool, length_scales);
}

}  // namespace multimodal_nvs
