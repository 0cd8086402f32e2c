// Dense kernels for the many small blocks of a supernodal factorization.
//
// OpenBLAS takes a process-wide lock to hand out its work buffers on every
// call: two threads factoring small supernodes spend their time queueing for
// it (8x8 dgemm: 1.02x throughput with 2 threads; 96x96: 2.0x). Blocks below a
// few thousand flops are computed here instead, with loops the compiler
// vectorizes; the choice depends on the block's size only, so the arithmetic
// is the same for any thread count.
//
// Runtime dispatch (docs/shipping.md): the library is built for x86-64-v2, and
// these loops also get AVX2 and AVX-512 versions (GCC function multiversioning:
// an ifunc picks one at load time by the CPU). Multiply-adds are never fused
// in any version (fp-contract off) and every entry is summed in the same
// order, so all versions give the same bits (ctest dispatch_paths; without
// fp-contract off the AVX2/AVX-512 factors differ from the baseline's).
#pragma once
#include <cmath>
#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX2__) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define LOCUS_DENSE_DISPATCH \
  __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4"), optimize("fp-contract=off")))
#else
#define LOCUS_DENSE_DISPATCH
#endif

namespace locus::dense {

// C (mm x kk, ld mm) = A * A(0:kk, :)^T for A (mm x kd, ld lda), lower part
// only: C(i, j) for i >= j. (The dsyrk + dgemm pair of a supernodal update.)
// Tiles of 8 rows x 4 columns stay in registers over the whole sum (one load of
// A's rows feeds four columns): 2-3x the plain loop's speed at these sizes.
// Every entry is summed over l in order, whatever the tiling.
// C never overlaps A (restrict): the last columns' loop then vectorizes.
LOCUS_DENSE_DISPATCH inline void syrk_gemm_lower(int mm, int kk, int kd, const double* __restrict A, int lda, double* __restrict C) {
  int j = 0;
  for (; j + 4 <= kk; j += 4) {
    double* c = C + static_cast<int64_t>(j) * mm;
    for (int i0 = j; i0 < mm; i0 += 8) {
      const int rows = mm - i0 < 8 ? mm - i0 : 8;
      double acc[4][8] = {};
      if (rows == 8) {
        for (int l = 0; l < kd; ++l) {
          const double* a = A + static_cast<int64_t>(l) * lda;
          const double s0 = a[j], s1 = a[j + 1], s2 = a[j + 2], s3 = a[j + 3];
          for (int r = 0; r < 8; ++r) {
            const double v = a[i0 + r];
            acc[0][r] += v * s0;
            acc[1][r] += v * s1;
            acc[2][r] += v * s2;
            acc[3][r] += v * s3;
          }
        }
      } else {
        for (int l = 0; l < kd; ++l) {
          const double* a = A + static_cast<int64_t>(l) * lda;
          const double s0 = a[j], s1 = a[j + 1], s2 = a[j + 2], s3 = a[j + 3];
          for (int r = 0; r < rows; ++r) {
            const double v = a[i0 + r];
            acc[0][r] += v * s0;
            acc[1][r] += v * s1;
            acc[2][r] += v * s2;
            acc[3][r] += v * s3;
          }
        }
      }
      // Rows above a column's diagonal in this tile are computed but never read.
      // A short tile is stored row by row through a switch: as a loop GCC
      // turns it into a `rep movs` per column, slow for a few words.
      for (int q = 0; q < 4; ++q) {
        double* dst = c + static_cast<int64_t>(q) * mm + i0;
        const double* src = acc[q];
        switch (rows) {
          case 8: dst[7] = src[7]; [[fallthrough]];
          case 7: dst[6] = src[6]; [[fallthrough]];
          case 6: dst[5] = src[5]; [[fallthrough]];
          case 5: dst[4] = src[4]; [[fallthrough]];
          case 4: dst[3] = src[3]; [[fallthrough]];
          case 3: dst[2] = src[2]; [[fallthrough]];
          case 2: dst[1] = src[1]; [[fallthrough]];
          default: dst[0] = src[0];
        }
      }
    }
  }
  for (; j < kk; ++j) {
    double* c = C + static_cast<int64_t>(j) * mm;
    for (int i = j; i < mm; ++i) c[i] = 0.0;
    for (int l = 0; l < kd; ++l) {
      const double* a = A + static_cast<int64_t>(l) * lda;
      const double s = a[j];
      for (int i = j; i < mm; ++i) c[i] += a[i] * s;
    }
  }
}

// In-place Cholesky of the m x k panel P (ld m): the k x k diagonal block gets
// its lower factor, the rows below are solved against it (dpotrf + dtrsm).
// Returns 0, or j + 1 when the pivot of column j is not positive (LAPACK's info).
LOCUS_DENSE_DISPATCH inline int panel_cholesky(int m, int k, double* P) {
  for (int j = 0; j < k; ++j) {
    double* pj = P + static_cast<int64_t>(j) * m;
    for (int l = 0; l < j; ++l) {
      const double* pl = P + static_cast<int64_t>(l) * m;
      const double s = pl[j];
      if (s == 0.0) continue;
      for (int i = j; i < m; ++i) pj[i] -= pl[i] * s;
    }
    const double d = pj[j];
    if (!(d > 0.0)) return j + 1;  // also NaN
    const double r = std::sqrt(d);
    pj[j] = r;
    const double inv = 1.0 / r;
    for (int i = j + 1; i < m; ++i) pj[i] *= inv;
  }
  return 0;
}

}  // namespace locus::dense
