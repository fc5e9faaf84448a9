// Scalar, bit-exact re-implementations of numpy's float64 np.exp / np.log on this machine.
//
// numpy 1.24.2 (numpy/core/src/umath/loops_exponent_log.dispatch.c.src, DOUBLE_exp / DOUBLE_log)
// runs, on an AVX512_SKX-class CPU with SVML linked (the Debian build is), simd_exp_f64 /
// simd_log_f64, which call Intel's vendored SVML kernels __svml_exp8 and __svml_log8
// (numpy/core/src/umath/svml/svml_z0_exp_d_la.s, svml_z0_log_d_la.s). numpy's own Tang-style
// AVX512F_exp_DOUBLE / AVX512F_log_DOUBLE kernels in the same file sit in the #else branch and
// are not used here. The algorithms below follow the SVML kernels instruction for instruction:
// every vfmadd/vfnmadd/vfmsub of the kernel is one std::fma here, every plain vmulpd/vaddpd/
// mulsd/addsd one plain operation (the package compiles with -ffp-contract=off, so the compiler
// fuses nothing on its own). The constants were read from the installed binary
// (_multiarray_umath.cpython-311-x86_64-linux-gnu.so, symbols __svml_dexp_data_internal_avx512,
// _imldExpHATab, __svml_dlog_data_internal_avx512); they differ in a few places from the SVML
// sources found in the numpy repository, and the binary is what numpy runs.
//
// SVML kernels are element-wise (the 8 lanes never interact), so a scalar version is exact.
#include "multimodal_nvs/core/depth/gp/numpy_math.hpp"
#include "multimodal_nvs/core/common/bit_cast.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace multimodal_nvs {
namespace {

// What an SSE/AVX operation returns for a NaN operand: the same NaN with the quiet bit set.
double quietNan(double x) {
  return bitCast<double>(bitCast<std::uint64_t>(x) | 0x0008000000000000ULL);
}

// The x86 "default NaN" (0/0 in SSE arithmetic): negative sign, quiet, zero payload.
constexpr std::uint64_t kDefaultNanBits = 0xfff8000000000000ULL;

// ---------------------------------------------------------------------------------------------
// exp: __svml_exp8 main path (|x| < 707.70, not NaN).
//
//   N = x*log2(e) truncated to 4 fractional bits, computed as one FMA x*log2e + Shifter in
//       round-toward-zero mode; Shifter = 1.5*2^48 + 1023, so the ulp of the sum is 2^-4 and
//       the 4 lowest mantissa bits of the sum are j = frac(N)*16 (the 1023 is a multiple of
//       16 and does not disturb them). N = sum - Shifter exactly, M = floor(N).
//   r = x - N*ln2, as two FMAs with ln2 split into high and low parts; 0 <= r < ln2/16
//       up to rounding.
//   exp(r) - 1 ~= r + c2 r^2 + r^3 (c3 + c4 r + r^2 (c5 + c6 r)), Estrin-like order.
//   exp(x) = 2^M * Th[j] * exp(r) = scalef(Th[j] + Th[j]*(exp(r)-1), N), Th[j] = 2^(j/16).
// ---------------------------------------------------------------------------------------------

constexpr double kExpTh[16] = {
    0x1.0000000000000p+0, 0x1.0b5586cf9890fp+0, 0x1.172b83c7d517bp+0, 0x1.2387a6e756238p+0,
    0x1.306fe0a31b715p+0, 0x1.3dea64c123422p+0, 0x1.4bfdad5362a27p+0, 0x1.5ab07dd485429p+0,
    0x1.6a09e667f3bcdp+0, 0x1.7a11473eb0187p+0, 0x1.8ace5422aa0dbp+0, 0x1.9c49182a3f090p+0,
    0x1.ae89f995ad3adp+0, 0x1.c199bdd85529cp+0, 0x1.d5818dcfba487p+0, 0x1.ea4afa2a490dap+0};
constexpr double kExpLog2e = 0x1.71547652b82fep+0;
constexpr double kExpShifter = 0x1.8000000003ff0p+48;  // 1.5*2^48 + 1023
constexpr double kExpLn2Hi = 0x1.62e42fefa39efp-1;
constexpr double kExpLn2Lo = 0x1.abc9e3b39803fp-56;
constexpr double kExpC2 = 0x1.0000000002622p-1;
constexpr double kExpC3 = 0x1.5555554b508a2p-3;
constexpr double kExpC4 = 0x1.555564bb4f5f0p-5;
constexpr double kExpC5 = 0x1.1106603d97c00p-7;
constexpr double kExpC6 = 0x1.72eb5ef0d213dp-10;
// Lanes with |x| >= this (and +-inf) are recomputed by the scalar "rare" routine below.
constexpr double kExpRareThreshold = 0x1.61da04cbafe44p+9;  // 707.703...

// fma(a, b, c) rounded toward zero, for the case a*b + c > 0 (the kernel's {rz-sae} FMA).
// The round-to-nearest FMA is off by at most half an ulp, and it rounded up exactly when the
// remainder a*b + c - rn is negative. A second FMA gives that remainder with the right sign
// (c - rn is exact here, and rounding never flips a sign or turns a nonzero remainder into 0
// at these magnitudes); step down one ulp when it is negative.
double fmaTowardZeroPositive(double a, double b, double c) {
  const double rn = std::fma(a, b, c);
  const double remainder = std::fma(a, b, c - rn);
  return remainder < 0.0 ? std::nextafter(rn, 0.0) : rn;
}

// ---------------------------------------------------------------------------------------------
// exp: __svml_dexp_cout_rare_internal, the scalar routine SVML runs for the lanes flagged above.
// A classic 64-entry table method in plain (non-fused) SSE2 arithmetic:
//   n = rint(x * 64/ln2), j = n mod 64, M = floor(n / 64), r = (x - n*L1) - n*L2,
//   exp(x) = 2^M * (T[j] + T[j]*(p(r) + t[j])) with T + t = 2^(j/64) as a double-double,
//   p(r) = r + r^2 (1/2 + r (c3 + r (c4 + r (c5 + r c6)))).
// Results that would be subnormal are formed at 2^60 times their size and scaled down at the
// end, with a hi/lo split so that the one final rounding is the correct one.
// ---------------------------------------------------------------------------------------------

constexpr double kExpHaHi[64] = {
    0x1.0000000000000p+0, 0x1.02c9a3e778061p+0, 0x1.059b0d3158574p+0, 0x1.0874518759bc8p+0,
    0x1.0b5586cf9890fp+0, 0x1.0e3ec32d3d1a2p+0, 0x1.11301d0125b51p+0, 0x1.1429aaea92de0p+0,
    0x1.172b83c7d517bp+0, 0x1.1a35beb6fcb75p+0, 0x1.1d4873168b9aap+0, 0x1.2063b88628cd6p+0,
    0x1.2387a6e756238p+0, 0x1.26b4565e27cddp+0, 0x1.29e9df51fdee1p+0, 0x1.2d285a6e4030bp+0,
    0x1.306fe0a31b715p+0, 0x1.33c08b26416ffp+0, 0x1.371a7373aa9cbp+0, 0x1.3a7db34e59ff7p+0,
    0x1.3dea64c123422p+0, 0x1.4160a21f72e2ap+0, 0x1.44e086061892dp+0, 0x1.486a2b5c13cd0p+0,
    0x1.4bfdad5362a27p+0, 0x1.4f9b2769d2ca7p+0, 0x1.5342b569d4f82p+0, 0x1.56f4736b527dap+0,
    0x1.5ab07dd485429p+0, 0x1.5e76f15ad2148p+0, 0x1.6247eb03a5585p+0, 0x1.6623882552225p+0,
    0x1.6a09e667f3bcdp+0, 0x1.6dfb23c651a2fp+0, 0x1.71f75e8ec5f74p+0, 0x1.75feb564267c9p+0,
    0x1.7a11473eb0187p+0, 0x1.7e2f336cf4e62p+0, 0x1.82589994cce13p+0, 0x1.868d99b4492edp+0,
    0x1.8ace5422aa0dbp+0, 0x1.8f1ae99157736p+0, 0x1.93737b0cdc5e5p+0, 0x1.97d829fde4e50p+0,
    0x1.9c49182a3f090p+0, 0x1.a0c667b5de565p+0, 0x1.a5503b23e255dp+0, 0x1.a9e6b5579fdbfp+0,
    0x1.ae89f995ad3adp+0, 0x1.b33a2b84f15fbp+0, 0x1.b7f76f2fb5e47p+0, 0x1.bcc1e904bc1d2p+0,
    0x1.c199bdd85529cp+0, 0x1.c67f12e57d14bp+0, 0x1.cb720dcef9069p+0, 0x1.d072d4a07897cp+0,
    0x1.d5818dcfba487p+0, 0x1.da9e603db3285p+0, 0x1.dfc97337b9b5fp+0, 0x1.e502ee78b3ff6p+0,
    0x1.ea4afa2a490dap+0, 0x1.efa1bee615a27p+0, 0x1.f50765b6e4540p+0, 0x1.fa7c1819e90d8p+0};
// Signed hex literals: clang-format would put one per line.
// clang-format off
constexpr double kExpHaLo[64] = {
    0x0.0p+0,               -0x1.160139cd8dc5dp-56, 0x1.cd2523567f613p-55,  0x1.0f74e61e6c861p-57,
    0x1.79aa65d837b6dp-54,  0x1.ebe3d702f9cd1p-60,  -0x1.556522a2fbd0ep-54, -0x1.1c923b9d5f416p-54,
    -0x1.01b15eaa59348p-55, 0x1.b898c3f1353bfp-55,  0x1.aecf73e3a2f60p-54,  0x1.a6f4144a6c38dp-55,
    0x1.68efde3a8a894p-54,  0x1.0472b981fe7f2p-55,  0x1.2f7e16d09ab31p-55,  0x1.b3782720c0ab4p-55,
    0x1.34d754db0abb6p-55,  0x1.fdd395dd3f84ap-55,  -0x1.24aedcc4b5068p-54, -0x1.1d1e83e9436d2p-56,
    0x1.59f48a72a4c6dp-55,  -0x1.8a78f4817895bp-58, 0x1.363ed60c2ac11p-59,  0x1.ecce1daa10379p-57,
    0x1.690cebb7aafb0p-56,  -0x1.f94340071a38ep-55, -0x1.8dec6bd0f385fp-56, 0x1.3350518fdd78ep-54,
    0x1.063e1e21c5409p-54,  0x1.432e62b64c035p-54,  -0x1.c33c53bef4da8p-55, -0x1.3cedd78565858p-54,
    -0x1.3b3efbf5e2228p-54, -0x1.367efb86da9eep-57, -0x1.81f647e5a3ecfp-56, -0x1.619321e55e68ap-55,
    -0x1.b32dcb94da51dp-56, 0x1.5ebe1abd66c55p-57,  -0x1.369b6f13b3734p-54, -0x1.4d450d872576ep-54,
    0x1.db72fc1f0eab4p-55,  0x1.bf68359f35f44p-56,  -0x1.da9b88b6c1e29p-58, -0x1.2434322f4f9aap-54,
    0x1.1affc2b91ce27p-56,  -0x1.7c50422622263p-55, -0x1.1bbd1d3bcbb15p-54, 0x1.469846e735ab3p-55,
    0x1.c1a7792cb3387p-55,  -0x1.5c3d956dcaebap-58, -0x1.8d6f438ad9334p-57, 0x1.4ffd70a5fddcdp-56,
    0x1.36eae30af0cb3p-56,  0x1.4e08fd10959acp-55,  0x1.76b2c6c921968p-57,  -0x1.fad5d3ffffa6fp-55,
    0x1.4a385a63d07a7p-56,  0x1.e5a50d5c192acp-55,  -0x1.2d52107b43e1fp-55, 0x1.4b604603a88d3p-56,
    -0x1.ff7128fd391f0p-55, 0x1.ec3bc41aa2008p-55,  0x1.a64a931d185eep-55,  0x1.7893b4d91cd9dp-56};
// clang-format on
constexpr double kExpHa64Log2e = 0x1.71547652b82fep+6;  // 64/ln2
constexpr double kExpHaRint = 0x1.8000000000000p+52;    // 1.5*2^52: rint by addition
constexpr double kExpHaL1 = 0x1.62e42fefa0000p-7;       // ln2/64, high part
constexpr double kExpHaL2 = 0x1.cf79abc9e3b3ap-46;      // ln2/64, low part
constexpr double kExpHaC2 = 0x1.0000000000000p-1;
constexpr double kExpHaC3 = 0x1.55555555548f8p-3;
constexpr double kExpHaC4 = 0x1.5555555558fccp-5;
constexpr double kExpHaC5 = 0x1.111123aaf20d3p-7;
constexpr double kExpHaC6 = 0x1.6c16a1c2a3ffdp-10;
constexpr double kExpHaOverflow = 0x1.62e42fefa39efp+9;    // x above this: +inf
constexpr double kExpHaSubnormal = -0x1.6232bdd7abcd2p+9;  // x below this: subnormal result
constexpr double kExpHaUnderflow = -0x1.74910d52d3051p+9;  // x below this: +0
constexpr double kExpHaHuge = 0x1.fffffffffffffp+1023;     // huge*huge = +inf
constexpr double kExpHaTiny = 0x1.0000000000001p-1022;     // tiny*tiny = +0
constexpr double kExpHaTwoM60 = 0x1.0000000000000p-60;
constexpr double kExpHaSplit = 0x1.8000000000000p+32;

// 2^e for a biased exponent field 1 <= e <= 2046 (0 gives +0, as in the kernel's bit surgery).
double powerOfTwoFromField(int biased) {
  return bitCast<double>(static_cast<std::uint64_t>(biased & 2047) << 52);
}

double expRare(double x) {
  const std::uint64_t bits = bitCast<std::uint64_t>(x);
  const int field = static_cast<int>((bits >> 52) & 2047);
  if (field == 2047) {                              // inf or NaN
    if (bits == 0xfff0000000000000ULL) return 0.0;  // exp(-inf) = +0
    return x * x;                                   // +inf (NaN never gets here)
  }
  if (field <= 970) return 1.0 + x;  // |x| < 2^-52; unreachable from numpyExp, kept for fidelity
  if (x > kExpHaOverflow) return kExpHaHuge * kExpHaHuge;
  if (x < kExpHaUnderflow) return kExpHaTiny * kExpHaTiny;

  const double shifted = x * kExpHa64Log2e + kExpHaRint;  // two roundings: mulsd, then addsd
  // The low 32 bits of the shifted value are n as a two's-complement integer.
  const std::int32_t n =
      static_cast<std::int32_t>(static_cast<std::uint32_t>(bitCast<std::uint64_t>(shifted)));
  const double nd = shifted - kExpHaRint;
  const int j = n & 63;
  const int m = n >> 6;  // floor(n / 64); the kernel only ever uses it modulo 2048
  const double r = (x - nd * kExpHaL1) - nd * kExpHaL2;
  double p = kExpHaC6 * r;
  p = (p + kExpHaC5) * r;
  p = (p + kExpHaC4) * r;
  p = (p + kExpHaC3) * r;
  p = (p + kExpHaC2) * r;
  p = p * r + r;
  p = (p + kExpHaLo[j]) * kExpHaHi[j];  // T*(p + t): the part added to T

  if (!(x < kExpHaSubnormal)) {
    const double result = p + kExpHaHi[j];
    const int field_out = (m + 1023) & 2047;
    // M = 1024 (x just below the overflow bound): scale by 2^1023, then by 2.
    if (field_out > 2046) return result * powerOfTwoFromField(field_out - 1) * 2.0;
    return result * powerOfTwoFromField(field_out);
  }
  // Subnormal result: compute 2^60 * exp(x) as hi + lo, then scale by 2^-60 once.
  const int field_up = (m + 1083) & 2047;
  const double scale = powerOfTwoFromField(field_up);
  const double lo = p * scale;
  const double hi = scale * kExpHaHi[j];
  const double sum = hi + lo;
  if (field_up <= 50) return sum * kExpHaTwoM60;
  // Result has more than a few significant bits: split sum into a 21-bit head and a tail so
  // that only the tail is rounded when scaling into the subnormal range.
  const double err = (hi - sum) + lo;
  const double big = sum * kExpHaSplit;
  const double head = (sum + big) - big;
  const double tail = err + (sum - head);
  return head * kExpHaTwoM60 + tail * kExpHaTwoM60;
}

// ---------------------------------------------------------------------------------------------
// log: __svml_log8 main path (x > 0 finite, subnormals included, or NaN).
//
//   x = 2^e * m with m in [1, 2) (vgetexppd / vgetmantpd, subnormals normalised).
//   rcp = VRCP14PD(m) rounded to 5 fractional bits, i.e. one of 16/32 .. 32/32.
//   R = rcp*m - 1 (one FMA), |R| <~ 2^-5.
//   log(x) = e*ln2 - log(rcp) + log1p(R); -log(rcp) comes from a 16-entry table indexed by the
//   top 4 mantissa bits of rcp. For rcp < 0.75 the table holds -log(2*rcp) and e is incremented.
//   log1p(R) ~= R + a2 R^2 + ... + a9 R^9, evaluated in the kernel's order as
//   R + R2*(R4*(R2*(a9 R + a8) + (a7 R + a6)) + (R2*(a5 R + a4) + (a3 R + a2))).
//   result = fma(ln2, e', T + poly), e' being e plus the table's correction.
//
// VRCP14PD is only specified to 2^-14 relative error. Measured exhaustively on this CPU, it
// depends on the top 20 mantissa bits of m only (plus m == 1 exactly, which rounds to 1 either
// way), is monotone, and after rounding to 5 fractional bits steps down by 1/32 exactly at the
// 16 mantissa prefixes below (top 16 mantissa bits; all 16 switching points fall on multiples
// of 2^-16). So rcp = 1 - k/32 with k = number of prefixes <= top16(m).
// ---------------------------------------------------------------------------------------------

constexpr std::uint32_t kLogRcpStepTop16[16] = {0x040f, 0x0c97, 0x15b4, 0x1f70, 0x29e6, 0x3523,
                                                0x4143, 0x4e5f, 0x5c99, 0x6c15, 0x7d07, 0x8f9c,
                                                0xa41a, 0xbad0, 0xd41c, 0xf080};
// Signed hex literals: clang-format would put one per line.
// clang-format off
constexpr double kLogTable[16] = {
    0x0.0p+0,              -0x1.f0a30c01162a6p-5, -0x1.e27076e2af2e6p-4, -0x1.5ff3070a793d4p-3,
    -0x1.c8ff7c79a9a22p-3, -0x1.1675cababa60ep-2, -0x1.4618bc21c5ec2p-2, -0x1.739d7f6bbd007p-2,
    0x1.269621134db92p-2,  0x1.f991c6cb3b379p-3,  0x1.a93ed3c8ad9e3p-3,  0x1.5bf406b543db2p-3,
    0x1.1178e8227e47cp-3,  0x1.9335e5d594989p-4,  0x1.08598b59e3a07p-4,  0x1.0415d89e74444p-5};
// clang-format on
constexpr double kLogA2 = -0x1.fffffffffffc6p-2;
constexpr double kLogA3 = 0x1.5555555555466p-2;
constexpr double kLogA4 = -0x1.00000000c05bdp-2;
constexpr double kLogA5 = 0x1.9999999cc9f5cp-3;
constexpr double kLogA6 = -0x1.55553fb28db06p-3;
constexpr double kLogA7 = 0x1.249229cee81efp-3;
constexpr double kLogA8 = -0x1.007357e93af62p-3;
constexpr double kLogA9 = 0x1.c81cd309d7c70p-4;
constexpr double kLogLn2 = 0x1.62e42fefa39efp-1;

// VRCP14PD(m) rounded to 5 fractional bits (vrndscalepd imm 0x58), for m in [1, 2).
double roundedReciprocal(double m) {
  const std::uint32_t top16 =
      static_cast<std::uint32_t>((bitCast<std::uint64_t>(m) >> 36) & 0xffff);
  int k = 0;
  while (k < 16 && kLogRcpStepTop16[k] <= top16)
    ++k;
  return static_cast<double>(32 - k) / 32.0;
}

}  // namespace

double numpyExp(double x) {
  // NaN lanes pass the kernel's arithmetic, which propagates the quietened input NaN.
  if (std::isnan(x)) return quietNan(x);
  if (!(std::fabs(x) < kExpRareThreshold)) return expRare(x);

  const double shifted = fmaTowardZeroPositive(x, kExpLog2e, kExpShifter);
  const double n = shifted - kExpShifter;  // exact: x*log2e truncated to a multiple of 1/16
  const int j = static_cast<int>(bitCast<std::uint64_t>(shifted) & 15);
  const int m = static_cast<int>(std::floor(n));

  double r = std::fma(-n, kExpLn2Hi, x);  // vfnmadd: x - n*ln2_hi
  r = std::fma(-kExpLn2Lo, n, r);         // vfnmadd: r - n*ln2_lo
  // (The kernel also clears exponent bit 62 of r, a no-op for |r| < 2, i.e. for all lanes that
  // reach this point.)
  const double r2 = r * r;
  const double p56 = std::fma(kExpC6, r, kExpC5);
  const double p34 = std::fma(kExpC4, r, kExpC3);
  const double r3 = r2 * r;
  const double p12 = std::fma(r2, kExpC2, r);
  const double p36 = std::fma(r2, p56, p34);
  const double expm1_r = std::fma(r3, p36, p12);
  const double scaled = std::fma(kExpTh[j], expm1_r, kExpTh[j]);
  // vscalefpd: scaled * 2^floor(n); exact here because |x| < 707.7 keeps the result normal.
  return std::ldexp(scaled, m);
}

double numpyLog(double x) {
  if (std::isnan(x)) return quietNan(x);
  // Lanes the kernel flags (vfpclasspd: +-0, +-inf, negative) go to __svml_dlog_cout_rare_internal.
  if (x == 0.0) return -std::numeric_limits<double>::infinity();  // -1/0
  if (x < 0.0) return bitCast<double>(kDefaultNanBits);           // 0/0: x86 default NaN
  if (std::isinf(x)) return x;                                    // +inf * +inf

  int e2 = 0;
  const double half_mant = std::frexp(x, &e2);  // x = half_mant * 2^e2, half_mant in [0.5, 1)
  const double m = half_mant * 2.0;             // vgetmantpd: [1, 2)
  double expo = static_cast<double>(e2 - 1);    // vgetexppd: floor(log2 x)

  const double rcp = roundedReciprocal(m);
  const double big_r = std::fma(rcp, m, -1.0);  // vfmsub: rcp*m - 1
  if (rcp < 0.75) expo = expo + 1.0;
  const double table = kLogTable[(bitCast<std::uint64_t>(rcp) >> 48) & 15];

  const double a76 = std::fma(big_r, kLogA7, kLogA6);
  const double a98 = std::fma(big_r, kLogA9, kLogA8);
  const double a32 = std::fma(big_r, kLogA3, kLogA2);
  const double r2 = big_r * big_r;
  const double a54 = std::fma(big_r, kLogA5, kLogA4);
  const double r4 = r2 * r2;
  const double hi = std::fma(r2, a98, a76);  // a6..a9
  const double lo = std::fma(r2, a54, a32);  // a2..a5
  const double tail = std::fma(r4, hi, lo);  // a2..a9
  const double poly = std::fma(r2, tail, big_r);
  const double sum = table + poly;
  return std::fma(kLogLn2, expo, sum);
}

}  // namespace multimodal_nvs
