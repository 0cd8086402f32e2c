// Eight doubles (one 64-byte row of an interleaved right-hand-side block) as
// xsimd batches: one AVX-512 register, two AVX2 or four SSE registers.
#pragma once
#include <xsimd/xsimd.hpp>

namespace locus {

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
    for (int q = 0; q < N; ++q) v[q] = xsimd::fma(b, x.v[q], v[q]);
  }
  // this -= a * x
  void fnma(double a, const Lane8& x) {
    const batch b(a);
    for (int q = 0; q < N; ++q) v[q] = xsimd::fnma(b, x.v[q], v[q]);
  }
  void scale(double a) {
    const batch b(a);
    for (int q = 0; q < N; ++q) v[q] = v[q] * b;
  }
  void sub(const Lane8& x) {
    for (int q = 0; q < N; ++q) v[q] = v[q] - x.v[q];
  }
};

}  // namespace locus
