#include "multimodal_nvs/core/depth/gp/reference_arithmetic.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include "multimodal_nvs/core/depth/gp/numpy_math.hpp"

namespace multimodal_nvs {
namespace {

int mostSignificantBit(std::size_t n) {
  int depth = 0;
  while (n >>= 1)
    ++depth;
  return depth;
}

// Moves a[i] down the max-heap a[1..n] (1-based, as numpy's implementation).
void siftDown(const std::int64_t* v, int* a, std::ptrdiff_t i, std::ptrdiff_t n) {
  const int moving = a[i];
  for (std::ptrdiff_t j = i << 1; j <= n; i = j, j += j) {
    if (j < n && v[a[j]] < v[a[j + 1]]) ++j;
    if (!(v[moving] < v[a[j]])) break;
    a[i] = a[j];
  }
  a[i] = moving;
}

// numpy's heapsort fallback of the introsort (taken when the recursion gets too deep).
void argHeapsort(const std::int64_t* v, int* tosort, std::ptrdiff_t n) {
  int* a = tosort - 1;
  for (std::ptrdiff_t l = n >> 1; l > 0; --l)
    siftDown(v, a, l, n);
  for (; n > 1; --n) {
    std::swap(a[1], a[n]);
    siftDown(v, a, 1, n - 1);
  }
}

}  // namespace

std::vector<int> numpyArgsortQuicksort(const std::vector<std::int64_t>& keys) {
  // numpy/core/src/npysort/quicksort.cpp, aquicksort_: median-of-three introsort with insertion
  // sort below 16 elements. Reproduced step by step because the order of equal keys matters.
  constexpr std::ptrdiff_t kSmallQuicksort = 15;
  const std::ptrdiff_t num = static_cast<std::ptrdiff_t>(keys.size());
  std::vector<int> order(num);
  for (std::ptrdiff_t i = 0; i < num; ++i)
    order[i] = static_cast<int>(i);
  if (num < 2) return order;
  const std::int64_t* v = keys.data();
  int* pl = order.data();
  int* pr = order.data() + num - 1;
  std::vector<int*> stack;
  std::vector<int> depth_stack;
  int cdepth = mostSignificantBit(num) * 2;
  for (;;) {
    if (cdepth < 0) {
      argHeapsort(v, pl, pr - pl + 1);
    } else {
      while ((pr - pl) > kSmallQuicksort) {
        int* pm = pl + ((pr - pl) >> 1);
        if (v[*pm] < v[*pl]) std::swap(*pm, *pl);
        if (v[*pr] < v[*pm]) std::swap(*pr, *pm);
        if (v[*pm] < v[*pl]) std::swap(*pm, *pl);
        const std::int64_t vp = v[*pm];
        int* pi = pl;
        int* pj = pr - 1;
        std::swap(*pm, *pj);
        for (;;) {
          do {
            ++pi;
          } while (v[*pi] < vp);
          do {
            --pj;
          } while (vp < v[*pj]);
          if (pi >= pj) break;
          std::swap(*pi, *pj);
        }
        int* pk = pr - 1;
        std::swap(*pi, *pk);
        if (pi - pl < pr - pi) {
          stack.push_back(pi + 1);
          stack.push_back(pr);
          pr = pi - 1;
        } else {
          stack.push_back(pl);
          stack.push_back(pi - 1);
          pl = pi + 1;
        }
        depth_stack.push_back(--cdepth);
      }
      for (int* pi = pl + 1; pi <= pr; ++pi) {
        const int vi = *pi;
        const std::int64_t vp = v[vi];
        int* pj = pi;
        int* pk = pi - 1;
        while (pj > pl && vp < v[*pk])
          *pj-- = *pk--;
        *pj = vi;
      }
    }
    if (stack.empty()) break;
    pr = stack.back();
    stack.pop_back();
    pl = stack.back();
    stack.pop_back();
    cdepth = depth_stack.back();
    depth_stack.pop_back();
  }
  return order;
}

std::vector<std::int64_t> referenceSampleRanks(const std::vector<AngularSample>& samples,
                                               double bin_deg) {
  // Keys as the reference forms them: floor(float32 angle / bin) as int32, packed into an int64
  // with the elevation bin in the low 32 bits (two's complement, masked). The azimuth bin is
  // scaled by 2^32 with a multiplication: left-shifting a negative value is undefined before
  // C++20, and |bx| < 2^31 keeps the product in range.
  const float bin32 = static_cast<float>(bin_deg);
  std::vector<std::int64_t> keys(samples.size());
  std::vector<std::int32_t> bx(samples.size()), by(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    bx[i] = static_cast<std::int32_t>(std::floor(samples[i].azimuth_deg / bin32));
    by[i] = static_cast<std::int32_t>(std::floor(samples[i].elevation_deg / bin32));
    keys[i] = (static_cast<std::int64_t>(bx[i]) * (std::int64_t(1) << 32)) |
              (static_cast<std::int64_t>(by[i]) & 0xFFFFFFFFLL);
  }
  const std::vector<int> order = numpyArgsortQuicksort(keys);
  std::vector<std::int64_t> position(samples.size());
  for (std::size_t p = 0; p < order.size(); ++p)
    position[order[p]] = static_cast<std::int64_t>(p);
  // Candidate bins are visited with the azimuth offset outermost and the (signed) elevation offset
  // inner, so across bins the order is lexicographic in (bx, by); inside a bin, argsort order.
  std::vector<std::int64_t> rank(samples.size());
  const std::int64_t n = static_cast<std::int64_t>(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    rank[i] =
        ((static_cast<std::int64_t>(bx[i]) * (std::int64_t(1) << 24) + by[i]) * n) + position[i];
  }
  return rank;
}

double referenceNllTwoSamples(double az0, double el0, double y0, double az1, double el1, double y1,
                              double amplitude, double noise, double length_scale) {
  const double a2 = amplitude * amplitude;
  const double l2 = length_scale * length_scale;
  const double da = az0 - az1;
  const double de = el0 - el1;
  const double d2 = da * da + de * de;
  // K = (a*a) * np.exp(-0.5 * d2 / (l*l)); diagonal += sigma^2. exp(-0.0) == 1 on the diagonal.
  const double k01 = a2 * numpyExp((-0.5 * d2) / l2);
  const double k00 = a2 * numpyExp((-0.5 * 0.0) / l2) + noise * noise;
  const double k11 = k00;
  // np.linalg.cholesky -> netlib dpotrf -> dpotrf2 (recursive): sqrt, dtrsm scales by the
  // reciprocal, dsyrk updates, sqrt. A non-positive or NaN pivot fails.
  if (!(k00 > 0.0)) return std::numeric_limits<double>::infinity();
  const double l00 = std::sqrt(k00);
  const double l10 = (1.0 / l00) * k01;
  const double a22 = (l10 != 0.0) ? k11 + (-1.0 * l10) * l10 : k11;
  if (!(a22 > 0.0)) return std::numeric_limits<double>::infinity();
  const double l11 = std::sqrt(a22);

  // v = np.linalg.solve(L, y): dgetrf2 on [[l00, 0], [l10, l11]] (no pivoting since l00 > |l10|),
  // multiplier (1/l00) * l10; dgetrs: unit-lower forward, then upper back substitution by division.
  const double m = (1.0 / l00) * l10;
  double t0 = y0, t1 = y1;
  if (t0 != 0.0) t1 = t1 - t0 * m;
  double v1 = t1, v0 = t0;
  if (v1 != 0.0) {
    v1 = v1 / l11;
    v0 = v0 - v1 * 0.0;
  }
  if (v0 != 0.0) v0 = v0 / l00;

  // alpha = np.linalg.solve(L.T, v): U = [[l00, l10], [0, l11]], unit-lower factor is identity.
  double a1 = v1, a0 = v0;
  if (a0 != 0.0) a1 = a1 - a0 * 0.0;
  if (a1 != 0.0) {
    a1 = a1 / l11;
    a0 = a0 - a1 * l10;
  }
  if (a0 != 0.0) a0 = a0 / l00;

  // quad = ddot(y, alpha) (netlib: sequential below 5 elements); logdet = 2 * sum(np.log(diag)).
  const double quad = (0.0 + y0 * a0) + y1 * a1;
  const double log_sum = numpyLog(l00) + numpyLog(l11);
  const double log_det = 2.0 * log_sum;
  return 0.5 * quad + 0.5 * log_det + 0.5 * 2 * std::log(2.0 * M_PI);
}

}  // namespace multimodal_nvs
