#pragma once
// Eight rows of an image as "lanes": a run of columns stored column by column, each column one
// 8-float vector holding that column of the eight rows. A recurrence along a row (a 1D solve)
// then runs on eight rows at once with vector arithmetic. The 8x8 transposes that move data in and
// out are the only architecture-specific code (AVX shuffles, else a plain loop: the same values).
#include <cstddef>

#ifdef __AVX__
#include <immintrin.h>
#endif

namespace multimodal_nvs {

constexpr int kLaneCount = 8;

/// One column of eight rows. GCC/Clang vector extension: its arithmetic is element-wise IEEE, so a
/// lane computes exactly what the same scalar expression computes (this package compiles without
/// floating-point contraction). May alias float: the transposes fill lanes through float pointers.
typedef float Lanes __attribute__((vector_size(kLaneCount * sizeof(float)), __may_alias__));

/// dst[i * dst_stride + j] = src[j * src_stride + i] for the 8x8 block; plain loop.
inline void transpose8x8Portable(const float* src, std::size_t src_stride, float* dst,
                                 std::size_t dst_stride) {
  for (int i = 0; i < kLaneCount; ++i)
    for (int j = 0; j < kLaneCount; ++j)
      dst[i * dst_stride + j] = src[j * src_stride + i];
}

/// The same 8x8 transpose; with AVX the classic unpack / shuffle / lane-permute sequence
/// (8 loads, 24 shuffles, 8 stores instead of 64 scalar moves).
inline void transpose8x8(const float* src, std::size_t src_stride, float* dst,
                         std::size_t dst_stride) {
#ifdef __AVX__
  const __m256 r0 = _mm256_loadu_ps(src), r1 = _mm256_loadu_ps(src + src_stride),
               r2 = _mm256_loadu_ps(src + 2 * src_stride),
               r3 = _mm256_loadu_ps(src + 3 * src_stride),
               r4 = _mm256_loadu_ps(src + 4 * src_stride),
               r5 = _mm256_loadu_ps(src + 5 * src_stride),
               r6 = _mm256_loadu_ps(src + 6 * src_stride),
               r7 = _mm256_loadu_ps(src + 7 * src_stride);
  // Pairs of rows interleaved, then pairs of pairs, then the 128-bit halves exchanged.
  const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1),
               t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3),
               t4 = _mm256_unpacklo_ps(r4, r5), t5 = _mm256_unpackhi_ps(r4, r5),
               t6 = _mm256_unpacklo_ps(r6, r7), t7 = _mm256_unpackhi_ps(r6, r7);
  const __m256 s0 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)),
               s1 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)),
               s2 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)),
               s3 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2)),
               s4 = _mm256_shuffle_ps(t4, t6, _MM_SHUFFLE(1, 0, 1, 0)),
               s5 = _mm256_shuffle_ps(t4, t6, _MM_SHUFFLE(3, 2, 3, 2)),
               s6 = _mm256_shuffle_ps(t5, t7, _MM_SHUFFLE(1, 0, 1, 0)),
               s7 = _mm256_shuffle_ps(t5, t7, _MM_SHUFFLE(3, 2, 3, 2));
  _mm256_storeu_ps(dst, _mm256_permute2f128_ps(s0, s4, 0x20));
  _mm256_storeu_ps(dst + dst_stride, _mm256_permute2f128_ps(s1, s5, 0x20));
  _mm256_storeu_ps(dst + 2 * dst_stride, _mm256_permute2f128_ps(s2, s6, 0x20));
  _mm256_storeu_ps(dst + 3 * dst_stride, _mm256_permute2f128_ps(s3, s7, 0x20));
  _mm256_storeu_ps(dst + 4 * dst_stride, _mm256_permute2f128_ps(s0, s4, 0x31));
  _mm256_storeu_ps(dst + 5 * dst_stride, _mm256_permute2f128_ps(s1, s5, 0x31));
  _mm256_storeu_ps(dst + 6 * dst_stride, _mm256_permute2f128_ps(s2, s6, 0x31));
  _mm256_storeu_ps(dst + 7 * dst_stride, _mm256_permute2f128_ps(s3, s7, 0x31));
#else
  transpose8x8Portable(src, src_stride, dst, dst_stride);
#endif
}

/// Rows [0, row_count) of `rows` (row_count <= 8, `stride` floats apart, `cols` each) into
/// `lanes[0, cols)`; the lanes of missing rows are zero.
inline void rowsToLanes(const float* rows, std::size_t stride, int row_count, int cols,
                        Lanes* lanes) {
  float* out = reinterpret_cast<float*>(lanes);
  int c = 0;
  if (row_count == kLaneCount) {
    for (; c + kLaneCount <= cols; c += kLaneCount)
      transpose8x8(rows + c, stride, out + std::size_t(c) * kLaneCount, kLaneCount);
  }
  for (; c < cols; ++c)
    for (int k = 0; k < kLaneCount; ++k)
      out[std::size_t(c) * kLaneCount + k] = k < row_count ? rows[k * stride + c] : 0.0f;
}

/// The inverse of rowsToLanes: `lanes[0, cols)` back into rows [0, row_count).
inline void lanesToRows(const Lanes* lanes, int row_count, int cols, float* rows,
                        std::size_t stride) {
  const float* in = reinterpret_cast<const float*>(lanes);
  int c = 0;
  if (row_count == kLaneCount) {
    for (; c + kLaneCount <= cols; c += kLaneCount)
      transpose8x8(in + std::size_t(c) * kLaneCount, kLaneCount, rows + c, stride);
  }
  for (; c < cols; ++c)
    for (int k = 0; k < row_count; ++k)
      rows[k * stride + c] = in[std::size_t(c) * kLaneCount + k];
}

}  // namespace multimodal_nvs
