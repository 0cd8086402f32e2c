// How a solve's accuracy is measured independently of the factor that made
// it (DESIGN.md "Numeric core" 5): a seeded random right-hand side, the same
// on every platform, and the relative residual ||A x - b|| / ||b|| with A
// applied by symmetric_multiply (the matrix itself, never the factor). The
// `factor` command and the benchmarks check their solves with these.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "locus/sparse_matrix.hpp"

namespace locus {

// n deterministic pseudo-random values in [-1, 1) from `seed` (splitmix64), the
// same on every platform, unlike std::uniform_real_distribution.
std::vector<double> random_vector(size_t n, uint64_t seed);

// ||A x - b|| / ||b|| (||A x - b|| when b = 0) for a lower-stored symmetric A.
double relative_residual(const CscMatrix& A, const double* x, const double* b);

}  // namespace locus
