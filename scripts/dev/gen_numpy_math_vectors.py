#!/usr/bin/python3
"""Generate the golden (input bits, numpy output bits) pairs of test/core/depth/gp/test_numpy_math.cpp.

Run once with the system numpy (Debian 12: numpy 1.24.2, /usr/bin/python3) on the machine whose
np.exp / np.log the C++ core must reproduce, and paste the two printed tables into the test:

    /usr/bin/python3 scripts/dev/gen_numpy_math_vectors.py

On an AVX512_SKX-class CPU numpy computes float64 exp/log with its vendored SVML kernels
(__svml_exp8 / __svml_log8), which differ from glibc's exp/log by one ulp on a large share of
arguments. The pairs are chosen mostly where numpy and glibc (Python's math module) disagree, so
that a fall-back to std::exp / std::log fails the test, plus the kernel's special regions:
exp's scalar "rare" path (|x| >= 707.70, subnormal results, overflow edge) and log arguments
whose mantissa lies between the measured VRCP14PD rounding steps and the exact-reciprocal ones.
The test must not depend on Python at run time, hence the pasted tables.
"""
import math
import struct
import sys
from fractions import Fraction

import numpy as np

SEED = 20240611
N_EXP = 200
N_LOG = 200

# Top 16 mantissa bits at which VRCP14PD(m), rounded to 5 fractional bits, steps down by 1/32
# (measured on the target CPU; mirrors kLogRcpStepTop16 in src/core/depth/gp/numpy_math.cpp).
RCP_STEPS = [0x040F, 0x0C97, 0x15B4, 0x1F70, 0x29E6, 0x3523, 0x4143, 0x4E5F,
             0x5C99, 0x6C15, 0x7D07, 0x8F9C, 0xA41A, 0xBAD0, 0xD41C, 0xF080]


def bits(x):
    return struct.unpack("<Q", struct.pack("<d", float(x)))[0]


def from_bits(b):
    return struct.unpack("<d", struct.pack("<Q", int(b)))[0]


def glibc(fn_math, x):
    """Python's math.exp / math.log (glibc), with IEEE results instead of exceptions."""
    try:
        return fn_math(x)
    except OverflowError:
        return math.inf
    except ValueError:
        return math.nan if x != 0.0 else -math.inf


def differs_from_glibc(fn_np, fn_math, xs):
    ys = fn_np(np.asarray(xs, dtype=np.float64))
    return [x for x, y in zip(xs, ys) if bits(y) != bits(glibc(fn_math, x))]


def pick(rng, fn_np, fn_math, draw, count, need_diff=True, keep=None):
    """`count` arguments from draw(rng, n): by default ones where numpy != glibc; with `keep`,
    ones that keep(xs) returns."""
    out = []
    while len(out) < count:
        xs = [float(v) for v in draw(rng, 4 * count)]
        if keep is not None:
            good = keep(xs)
        elif need_diff:
            good = differs_from_glibc(fn_np, fn_math, xs)
        else:
            good = xs
        out.extend(good[: count - len(out)])
    return out


# --- A Python model of numpy's log kernel (SVML __svml_log8 main path), used only to find
# --- arguments whose result depends on the VRCP14PD reciprocal (see src/core/depth/gp/numpy_math.cpp).
LOG_TABLE = [float.fromhex(h) for h in (
    "0x0.0p+0", "-0x1.f0a30c01162a6p-5", "-0x1.e27076e2af2e6p-4", "-0x1.5ff3070a793d4p-3",
    "-0x1.c8ff7c79a9a22p-3", "-0x1.1675cababa60ep-2", "-0x1.4618bc21c5ec2p-2",
    "-0x1.739d7f6bbd007p-2", "0x1.269621134db92p-2", "0x1.f991c6cb3b379p-3",
    "0x1.a93ed3c8ad9e3p-3", "0x1.5bf406b543db2p-3", "0x1.1178e8227e47cp-3",
    "0x1.9335e5d594989p-4", "0x1.08598b59e3a07p-4", "0x1.0415d89e74444p-5")]
LOG_A = {k: float.fromhex(h) for k, h in (
    (2, "-0x1.fffffffffffc6p-2"), (3, "0x1.5555555555466p-2"), (4, "-0x1.00000000c05bdp-2"),
    (5, "0x1.9999999cc9f5cp-3"), (6, "-0x1.55553fb28db06p-3"), (7, "0x1.249229cee81efp-3"),
    (8, "-0x1.007357e93af62p-3"), (9, "0x1.c81cd309d7c70p-4"))}
LN2 = float.fromhex("0x1.62e42fefa39efp-1")


def fma(a, b, c):
    """Correctly rounded a*b + c (int / int true division rounds correctly in CPython)."""
    return float(Fraction(a) * Fraction(b) + Fraction(c))


def model_log(x, hardware_rcp):
    """numpy's log of a positive normal x, with the hardware reciprocal or the exact one."""
    half, e2 = math.frexp(x)
    m, expo = 2.0 * half, float(e2 - 1)
    if hardware_rcp:
        top16 = (bits(m) >> 36) & 0xFFFF
        rcp = (32 - sum(1 for s in RCP_STEPS if s <= top16)) / 32.0
    else:
        rcp = round(Fraction(32) / Fraction(m)) / 32.0
    r = fma(rcp, m, -1.0)
    if rcp < 0.75:
        expo = expo + 1.0
    t = LOG_TABLE[(bits(rcp) >> 48) & 15]
    a = LOG_A
    a76, a98, a32 = fma(r, a[7], a[6]), fma(r, a[9], a[8]), fma(r, a[3], a[2])
    r2 = r * r
    a54 = fma(r, a[5], a[4])
    r4 = r2 * r2
    tail = fma(r4, fma(r2, a98, a76), fma(r2, a54, a32))
    return fma(LN2, expo, t + fma(r2, tail, r))


def depends_on_hardware_rcp(xs):
    ys = np.log(np.asarray(xs, dtype=np.float64))
    out = []
    for x, y in zip(xs, ys):
        assert bits(model_log(x, True)) == bits(y), f"model != np.log at {x!r}"
        if bits(model_log(x, False)) != bits(y):
            out.append(x)
    return out


def exp_arguments(rng):
    u = lambda lo, hi: (lambda r, n: r.uniform(lo, hi, n))
    args = []
    args += pick(rng, np.exp, math.exp, u(-5000.0, 0.0), 40)  # kernel matrices, mostly tiny/0
    args += pick(rng, np.exp, math.exp, lambda r, n: -(10.0 ** r.uniform(-6, 3.7, n)), 48)
    args += pick(rng, np.exp, math.exp, u(-50.0, 50.0), 25)
    args += pick(rng, np.exp, math.exp, u(-1.0, 1.0), 20)
    args += pick(rng, np.exp, math.exp, u(-707.7, 709.0), 20)
    # SVML's scalar rare path: subnormal results, both of its sub-branches, and the top edge.
    args += pick(rng, np.exp, math.exp, u(-745.13, -716.0), 12)
    args += pick(rng, np.exp, math.exp, u(-716.0, -707.71), 12, need_diff=False)
    args += pick(rng, np.exp, math.exp, u(707.71, 709.78), 8, need_diff=False)
    # Boundaries of the main/rare split and of overflow/underflow.
    for x in (707.7032713517042, -707.7032713517042, 709.782712893384, -708.3964185322641,
              -745.1332191019411):
        args += [from_bits(bits(x) - 1), x, from_bits(bits(x) + 1)]
    assert len(args) == N_EXP, len(args)
    return args


def log_arguments(rng):
    u = lambda lo, hi: (lambda r, n: r.uniform(lo, hi, n))
    args = []
    args += pick(rng, np.log, math.log, u(0.1, 30.0), 60)
    args += pick(rng, np.log, math.log, lambda r, n: 625.25 * (1 + r.uniform(-1e-3, 1e-3, n)), 15)
    args += pick(rng, np.log, math.log, lambda r, n: 25.0 * (1 + r.uniform(-1e-3, 1e-3, n)), 15)
    args += pick(rng, np.log, math.log, lambda r, n: 10.0 ** r.uniform(-300, 300, n), 30)
    args += pick(rng, np.log, math.log, u(0.5, 2.0), 20)
    args += pick(rng, np.log, math.log, u(0.98, 1.02), 10)

    def denormals(r, n):
        return [from_bits(b) for b in r.integers(1, 2**52, n, dtype=np.uint64)]

    args += pick(rng, np.log, math.log, denormals, 10)

    # Mantissas between the hardware reciprocal step and the exact 1/m rounding step, kept where
    # a log that rounded the exact reciprocal instead of VRCP14PD's estimate gives other bits.
    def near_rcp_steps(r, n):
        xs = []
        for _ in range(n):
            k = int(r.integers(0, 16))
            rcp_hi = (32 - k) / 32.0  # rounded reciprocal just below the step
            m_exact = 2.0 / (rcp_hi + (32 - k - 1) / 32.0)  # exact 1/m rounding boundary
            top_exact = int((m_exact - 1.0) * 2**16)
            lo_top, hi_top = sorted((RCP_STEPS[k], top_exact))
            top = int(r.integers(lo_top, hi_top + 1))
            low = int(r.integers(0, 2**36))
            expo = int(r.integers(1000, 1046))
            xs.append(from_bits((expo << 52) | (top << 36) | low))
        return xs

    args += pick(rng, np.log, math.log, near_rcp_steps, 40, keep=depends_on_hardware_rcp)
    assert len(args) == N_LOG, len(args)
    return args


def print_table(name, xs, fn_np):
    ys = fn_np(np.asarray(xs, dtype=np.float64))
    print(f"// {len(xs)} pairs, {name}: generated by scripts/dev/gen_numpy_math_vectors.py "
          f"(numpy {np.__version__})")
    print(f"const BitsPair k{name}Golden[] = {{")
    for x, y in zip(xs, ys):
        print(f"    {{0x{bits(x):016x}ULL, 0x{bits(y):016x}ULL}},")
    print("};")


def main():
    rng = np.random.default_rng(SEED)
    with np.errstate(all="ignore"):
        exp_args = exp_arguments(rng)
        log_args = log_arguments(rng)
        print_table("Exp", exp_args, np.exp)
        print_table("Log", log_args, np.log)
        n_exp = len(differs_from_glibc(np.exp, math.exp, exp_args))
        n_log = len(differs_from_glibc(np.log, math.log, log_args))
    print(f"# numpy != glibc on {n_exp}/{len(exp_args)} exp and {n_log}/{len(log_args)} log pairs",
          file=sys.stderr)


if __name__ == "__main__":
    main()
