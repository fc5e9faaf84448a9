#pragma once
// numpy's float64 exp and log reproduced bit for bit (parity with the published reference code).
namespace multimodal_nvs {

/// numpy's float64 `np.exp` and `np.log`, reproduced bit for bit, one value at a time.
///
/// Why: the Python reference picks the GP length scale with a golden-section search over a
/// marginal likelihood that is built from `625 * np.exp(-0.5 * d2 / l^2)` and `np.log`. Near the
/// optimum the likelihood is flat down to the last bit, so a one-ulp difference in a single
/// exp/log can flip a comparison of the search and send it to a different length scale. glibc's
/// exp/log differ from numpy's by one ulp on roughly a quarter of all arguments, so the C++ core
/// needs numpy's exact results to keep that search in parity with the reference.
///
/// Which kernel: numpy 1.24.2 (Debian 12, /usr/bin/python3) dispatches float64 exp/log on an
/// AVX512_SKX-class CPU (this machine: AMD EPYC with AVX512F/CD/BW/DQ/VL) to Intel's SVML kernels
/// `__svml_exp8` and `__svml_log8` that numpy vendors (numpy/core/src/umath/svml/
/// svml_z0_exp_d_la.s and svml_z0_log_d_la.s, called from `simd_exp_f64` / `simd_log_f64` in
/// numpy/core/src/umath/loops_exponent_log.dispatch.c.src). numpy's own `AVX512F_exp_DOUBLE` /
/// `AVX512F_log_DOUBLE` in that file are only the fallback for CPUs with AVX512F but without
/// AVX512_SKX; the installed binary calls the SVML kernels (checked with objdump), and those
/// are what these functions reproduce. Verified against numpy on 10^7-argument sweeps with zero
/// mismatching bits (see test/core/depth/gp/test_numpy_math.cpp and scripts/dev/
/// gen_numpy_math_vectors.py).
///
/// Special values follow numpy: exp(NaN) and log(NaN) return the input NaN quietened (sign and
/// payload kept); exp(+inf) = +inf, exp(-inf) = +0, exp overflows to +inf above 709.78 and
/// flushes to +0 below -745.13 (with numpy's subnormal results in between); log(+-0) = -inf,
/// log(+inf) = +inf, log(x < 0) and log(-inf) return the x86 default NaN (sign bit set). No
/// floating-point exceptions or errno are promised.
///
/// Caveat: log's range reduction uses the VRCP14PD reciprocal estimate, whose low bits are not
/// specified by the ISA. The reduction only needs which of 17 values it rounds to; the switching
/// points were measured on this CPU (see numpy_math.cpp). Another CPU family may switch a few
/// mantissas earlier or later, in which case numpy itself gives different bits there.
double numpyExp(double x);

/// See numpyExp: numpy's float64 `np.log` (SVML `__svml_log8`), bit for bit.
double numpyLog(double x);

}  // namespace multimodal_nvs
