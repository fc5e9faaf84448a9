#pragma once
// Bit-level emulation of the published Python reference where parity depends on it.
//
// When a neighbour set has two samples far apart relative to the length scale, the marginal
// likelihood is flat to the last bit over a wide range of length scales, so the golden-section
// search is steered by rounding. The reference's result there depends on numpy's own float64
// exp/log kernels, on the order of operations in netlib LAPACK/BLAS (dpotrf2, dgetrf2, dgetrs,
// ddot) and on the order in which the reference lists the two samples. Two-sample sets cause
// ~85% of all disagreements with a plain implementation, so for them we reproduce all of that.
#include <cstdint>
#include <vector>

#include "multimodal_nvs/core/depth/angular_samples.hpp"

namespace multimodal_nvs {

/// numpy's np.argsort(keys) with the default (introsort) kind, int64 keys: the same permutation,
/// including the (unstable) order of equal keys.
std::vector<int> numpyArgsortQuicksort(const std::vector<std::int64_t>& keys);

/// The position at which the reference lists each sample in a neighbour set: bins of side
/// `bin_deg` visited in (bin_az, bin_el) order, and inside a bin the argsort order of the keys.
/// Returns a rank per sample; sorting a set's members by rank gives the reference order.
std::vector<std::int64_t> referenceSampleRanks(const std::vector<AngularSample>& samples,
                                               double bin_deg);

/// The reference's negative log marginal likelihood of a two-sample set, bit for bit: kernel
/// (a^2) * np.exp((-0.5 * d2) / (l * l)), np.linalg.cholesky (netlib dpotrf2), two
/// np.linalg.solve (netlib dgesv), the ddot quad form, np.log of the diagonal. +inf when the
/// Cholesky fails. Samples must be in reference order.
double referenceNllTwoSamples(double az0, double el0, double y0, double az1, double el1, double y1,
                              double amplitude, double noise, double length_scale);

}  // namespace multimodal_nvs
