// Eight doubles (one 64-byte row of an interleaved right-hand-side block) as
// xsimd batches: one AVX-512 register, two AVX2 or four SSE registers.
#pragma once
#include <cmath>

#include <xsimd/xsimd.hpp>
#if defined(__FMA__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace locus {

// Multiply-adds are fused exactly where the target has FMA instructions, in
// every build. xsimd 8.1 has no fused double multiply-add for AVX-512 and
// writes it as x * y + z, which the compiler fuses or not depending on
// optimization and instrumentation (fused in Release, separate under -O0 or
// the sanitizers), so the same solve gave different last bits in Release and
// in the sanitizer build, and a one-lane solve (scalar) stopped matching its
// lane of a wide one (vector). Scalar code that must match a lane uses
// fnma_scalar.
#if defined(__FMA__) || defined(__AVX512F__)
inline constexpr bool kFusedMultiplyAdd = true;
#else
inline constexpr bool kFusedMultiplyAdd = false;
#endif

// v - a x, rounded as one lane of Lane8::fnma.
inline double fnma_scalar(double a, double x, double v) {
  if constexpr (kFusedMultiplyAdd) return std::fma(-a, x, v);
  else return v - a * x;
}

struct Lane8 {
  using batch = xsimd::batch<double>;
  static constexpr int W = static_cast<int>(batch::size);
  static constexpr int N = 8 / W;
  static_assert(N * W == 8, "SIMD width must divide 8");
  batch v[N];

  static Lane8 load(const double* p) {
    Lane8 r;
    for (int q = 0; q < N; ++q) r.v[q] = batch::load_unaligned(p + q * W);
    return r;
  }
  static Lane8 zero() {
    Lane8 r;
    for (int q = 0; q < N; ++q) r.v[q] = batch(0.0);
    return r;
  }
  void store(double* p) const {
    for (int q = 0; q < N; ++q) v[q].store_unaligned(p + q * W);
  }
  // this += a * x
  void fma(double a, const Lane8& x) {
    const batch b(a);
    for (int q = 0; q < N; ++q) v[q] = fused(b, x.v[q], v[q], false);
  }
  // this -= a * x
  void fnma(double a, const Lane8& x) {
    const batch b(a);
    for (int q = 0; q < N; ++q) v[q] = fused(b, x.v[q], v[q], true);
  }
  void scale(double a) {
    const batch b(a);
    for (int q = 0; q < N; ++q) v[q] = v[q] * b;
  }
  void sub(const Lane8& x) {
    for (int q = 0; q < N; ++q) v[q] = v[q] - x.v[q];
  }

 private:
  // z + b x (or z - b x), one rounding where the target has FMA (see kFusedMultiplyAdd).
  static batch fused(const batch& b, const batch& x, const batch& z, bool negate) {
#if defined(__AVX512F__)
    static_assert(W == 8, "AVX-512: one 8-double register");
    return batch(negate ? _mm512_fnmadd_pd(b, x, z) : _mm512_fmadd_pd(b, x, z));
#elif defined(__FMA__) && defined(__AVX__)
    static_assert(W == 4, "AVX: 4-double registers");
    return batch(negate ? _mm256_fnmadd_pd(b, x, z) : _mm256_fmadd_pd(b, x, z));
#elif defined(__FMA__)
    static_assert(W == 2, "SSE: 2-double registers");
    return batch(negate ? _mm_fnmadd_pd(b, x, z) : _mm_fmadd_pd(b, x, z));
#else
    return negate ? z - b * x : z + b * x;  // no FMA instructions: nothing to fuse
#endif
  }
};

}  // namespace locus
