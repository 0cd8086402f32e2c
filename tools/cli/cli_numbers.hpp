// Small numeric helpers of the tools and benchmarks: medians of repeats,
// deterministic random vectors, residuals of a solve.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "locus/sparse_matrix.hpp"

namespace locus::cli {

// Median of a non-empty sample (mean of the two middle values for even sizes).
double median(std::vector<double> v);

// n deterministic pseudo-random values in [-1, 1) from `seed` (splitmix64), the
// same on every platform, unlike std::uniform_real_distribution.
std::vector<double> random_vector(size_t n, uint64_t seed);

// ||A x - b|| / ||b|| for a lower-stored symmetric A.
double relative_residual(const CscMatrix& A, const double* x, const double* b);

}  // namespace locus::cli
