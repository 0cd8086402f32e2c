// The seeded right-hand side and the residual of a solve
// (kernels/include/locus/kernels/solve/solve_accuracy.hpp).
#include "locus/kernels/solve/solve_accuracy.hpp"

#include <cmath>


namespace locus {

std::vector<double> random_vector(size_t n, uint64_t seed) {
  std::vector<double> v(n);
  uint64_t s = seed;
  for (size_t i = 0; i < n; ++i) {
    // splitmix64 (Steele, Lea, Flood 2014): a full-period, well-mixed 64-bit stream.
    uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    v[i] = static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;  // 53 random bits -> [-1, 1)
  }
  return v;
}

double relative_residual(const CscMatrix& A, const double* x, const double* b) {
  std::vector<double> ax(static_cast<size_t>(A.nrows));
  symmetric_multiply(A, x, ax.data());
  double rr = 0, bb = 0;
  for (int32_t i = 0; i < A.nrows; ++i) {
    const double d = ax[i] - b[i];
    rr += d * d;
    bb += b[i] * b[i];
  }
  return bb > 0 ? std::sqrt(rr / bb) : std::sqrt(rr);
}

}  // namespace locus
