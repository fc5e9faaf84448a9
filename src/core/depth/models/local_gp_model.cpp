#include "multimodal_nvs/core/depth/models/local_gp_model.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "multimodal_nvs/core/common/per_worker.hpp"
#include "multimodal_nvs/core/depth/gp/batched_length_scale_search.hpp"
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"
#include "multimodal_nvs/core/depth/gp/length_scale_search.hpp"
#include "multimodal_nvs/core/depth/gp/local_gp.hpp"
#include "multimodal_nvs/core/depth/gp/reference_arithmetic.hpp"

namespace multimodal_nvs {
std::vector<double> shiftedTargets(const std::vector<AngularSample>& samples, double shift) {
  std::vector<double> y(samples.size());
  const float shift32 = static_cast<float>(shift);
  for (std::size_t i = 0; i < samples.size(); ++i)
    y[i] = samples[i].depth - shift32;
  return y;
}

void predictLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                    ThreadPool& pool, PixelPredictions& out) {
  predictLocalGp(samples, shiftedTargets(samples, shift), angles, sets, params, PriorMean{shift},
                 pool, out);
}

void predictLocalGp(const std::vector<AngularSample>& samples, const std::vector<double>& targets,
                    const PixelAngleGrid& angles, const NeighbourSets& sets,
                    const DepthCompletionParams& params, const PriorMean& prior, ThreadPool& pool,
                    PixelPredictions& out, PredictionPrecision precision,
                    const std::function<void(int row)>& finish_row) {
  const LocalGpParams& gp = params.gp;
  // Sized only: the per-pixel pass below writes every pixel, the prior wherever no solved set
  // reaches, in the same row pass (a separate full-image fill measured ~3 % of a radar frame).
  const std::size_t pixel_count = static_cast<std::size_t>(angles.grid().size());
  out.mean.resize(pixel_count);
  out.variance.resize(pixel_count);

  // Storage for every set's posterior, laid out by prefix sums so sets can be solved in parallel.
  const int set_count = sets.setCount();
  std::vector<std::size_t> factor_offset(set_count + 1, 0), member_offset(set_count + 1, 0);
  for (int s = 0; s < set_count; ++s) {
    const std::size_t n = sets.setSize(s);
    factor_offset[s + 1] = factor_offset[s] + n * (n + 1) / 2;
    member_offset[s + 1] = member_offset[s] + n;
  }
  std::vector<double> factors(factor_offset[set_count]);
  std::vector<double> betas(member_offset[set_count]);
  std::vector<float> member_az(member_offset[set_count]), member_el(member_offset[set_count]);
  std::vector<double> member_y(member_offset[set_count]);
  std::vector<double> length_scales(set_count);
  std::vector<std::uint8_t> solved(set_count, 0);

  // Two-sample sets are searched with the reference's exact arithmetic (see
  // reference_arithmetic.hpp), which needs the reference's order of the two samples.
  const std::vector<std::int64_t> rank = referenceSampleRanks(samples, params.radius_deg);

  // Gather every set's samples once.
  for (int s = 0; s < set_count; ++s) {
    const int* members = sets.members(s);
    for (int i = 0; i < sets.setSize(s); ++i) {
      member_az[member_offset[s] + i] = samples[members[i]].azimuth_deg;
      member_el[member_offset[s] + i] = samples[members[i]].elevation_deg;
      member_y[member_offset[s] + i] = targets[members[i]];
    }
  }

  // 1. Length scales. Sets of 3..32 samples go in batches of equal size, one set per SIMD lane.
  const auto set_data = [&](int s) {
    const std::size_t first = member_offset[s];
    return SearchSet{sets.setSize(s), member_az.data() + first, member_el.data() + first,
                     member_y.data() + first};
  };
  const std::vector<int> singles =  // sets searched one at a time
      searchInEqualSizeBatches(precision, set_count, set_data, gp, pool, length_scales);
  PerWorker<LocalGp> gps(pool.size(), LocalGp(gp));
  pool.parallelFor(static_cast<long long>(singles.size()), [&](long long k, int worker) {
    const int s = singles[k];
    const int n = sets.setSize(s);
    const float* az = member_az.data() + member_offset[s];
    const float* el = member_el.data() + member_offset[s];
    const double* y = member_y.data() + member_offset[s];
    if (n == 1) {
      // K = a^2 + sigma^2 whatever the length scale: every comparison of the search is a tie, so
      // its path is fixed and needs no likelihood evaluation.
      length_scales[s] =
          goldenSectionMinimize([](double) { return 0.0; }, gp.length_scale_min,
                                gp.length_scale_max, gp.tolerance, gp.max_iterations);
    } else if (n == 2) {
      const int* members = sets.members(s);
      const int first = rank[members[0]] <= rank[members[1]] ? 0 : 1, second = 1 - first;
      length_scales[s] = goldenSectionMinimize(
          [&](double l) {
            return referenceNllTwoSamples(az[first], el[first], y[first], az[second], el[second],
                                          y[second], gp.amplitude, gp.noise, l);
          },
          gp.length_scale_min, gp.length_scale_max, gp.tolerance, gp.max_iterations);
    } else {
      gps[worker].setData(az, el, y, n);
      length_scales[s] = gps[worker].searchLengthScale();
    }
  });

  // 2. One factorisation per set at its length scale.
  struct Factors {
    std::vector<double> factor, beta;
  };
  PerWorker<Factors> scratch(pool.size());
  pool.parallelFor(
      set_count,
      [&](long long set_index, int worker) {
        const int s = static_cast<int>(set_index);
        const int n = sets.setSize(s);
        LocalGp& local = gps[worker];
        local.setData(member_az.data() + member_offset[s], member_el.data() + member_offset[s],
                      member_y.data() + member_offset[s], n);
        Factors& f = scratch[worker];
        if (!local.posterior(length_scales[s], f.factor, f.beta)) return;  // prior stays
        std::copy(f.factor.begin(), f.factor.end(), factors.begin() + factor_offset[s]);
        std::copy(f.beta.begin(), f.beta.end(), betas.begin() + member_offset[s]);
        solved[s] = 1;
      },
      32);  // 32 sets a chunk: neighbouring sets' `solved` bytes share a cache line

  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  const float prior_mean = static_cast<float>(prior.constant);
  const float prior_variance = static_cast<float>(gp.priorVariance());
  // Rows go in bands, and each set's segments in a band in one call: a set reaches a few
  // neighbouring rows with one ~15-pixel segment each, and one call per segment left most SIMD
  // lanes of its blocks empty and paid the set-up per segment.
  constexpr int kBandRows = 4;
  struct BandScratch {
    std::vector<int> group_of, stamp;  // per set: its group, valid where stamp = the band
    std::vector<int> group_set, group_start, cursor;  // per group: its set, its first run
    std::vector<const NeighbourSegment*> segments;    // the band's solved segments
    std::vector<PixelRun> runs;                       // the segments' pixels, by group
  };
  PerWorker<BandScratch> scratch_bands(pool.size());
  const long long bands = (rows + kBandRows - 1) / kBandRows;
  pool.parallelFor(bands, [&](long long band_index, int worker) {
    const int r0 = static_cast<int>(band_index) * kBandRows;
    const int r1 = std::min(rows, r0 + kBandRows);
    BandScratch& b = scratch_bands[worker];
    if (b.stamp.empty()) {
      b.stamp.assign(set_count, -1);
      b.group_of.resize(set_count);
    }
    b.segments.clear();
    b.group_set.clear();
    // The prior wherever no solved set reaches; the solved segments, grouped by set.
    for (int row = r0; row < r1; ++row) {
      float* mean_row = out.mean.data() + std::size_t(row) * cols;
      float* variance_row = out.variance.data() + std::size_t(row) * cols;
      int filled_to = 0;  // pixels before this column are written or in a solved segment
      const auto fill_prior = [&](int end) {
        std::fill(mean_row + filled_to, mean_row + end, prior_mean);
        std::fill(variance_row + filled_to, variance_row + end, prior_variance);
        filled_to = end;
      };
      for (std::size_t k = sets.rowBegin(row); k < sets.rowBegin(row + 1); ++k) {
        const NeighbourSegment& seg = sets.segments()[k];
        if (!solved[seg.set_id]) continue;  // its pixels keep the prior
        fill_prior(seg.col_begin);
        filled_to = seg.col_end;
        if (b.stamp[seg.set_id] != static_cast<int>(band_index)) {
          b.stamp[seg.set_id] = static_cast<int>(band_index);
          b.group_of[seg.set_id] = static_cast<int>(b.group_set.size());
          b.group_set.push_back(seg.set_id);
        }
        b.segments.push_back(&seg);
      }
      fill_prior(cols);
    }
    // Counting sort of the segments by group, then one call per group.
    const int groups = static_cast<int>(b.group_set.size());
    b.group_start.assign(groups + 1, 0);
    for (const NeighbourSegment* seg : b.segments)
      ++b.group_start[b.group_of[seg->set_id] + 1];
    for (int g = 0; g < groups; ++g)
      b.group_start[g + 1] += b.group_start[g];
    b.cursor.assign(b.group_start.begin(), b.group_start.end() - 1);
    b.runs.resize(b.segments.size());
    for (const NeighbourSegment* segment : b.segments) {
      const NeighbourSegment& seg = *segment;
      const std::size_t pixel = std::size_t(seg.row) * cols + seg.col_begin;
      b.runs[b.cursor[b.group_of[seg.set_id]]++] = {
          angles.azimuthRow(seg.row) + seg.col_begin, angles.elevationRow(seg.row) + seg.col_begin,
          out.mean.data() + pixel, out.variance.data() + pixel, seg.col_end - seg.col_begin};
    }
    for (int g = 0; g < groups; ++g) {
      const int set = b.group_set[g];
      const std::size_t member = member_offset[set];
      predictFromFactor(factors.data() + factor_offset[set], betas.data() + member,
                        member_az.data() + member, member_el.data() + member, sets.setSize(set),
                        length_scales[set], gp, b.runs.data() + b.group_start[g],
                        b.group_start[g + 1] - b.group_start[g], prior.constant, precision);
    }
    if (finish_row) {
      for (int row = r0; row < r1; ++row)
        finish_row(row);
    }
  });
}

}  // namespace multimodal_nvs
