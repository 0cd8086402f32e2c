// Small numeric helpers of the tools and benchmarks: medians of repeats,
// deterministic random vectors, residuals of a solve.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "locus/kernels/solve/solve_accuracy.hpp"

namespace locus::cli {

// Median of a non-empty sample (mean of the two middle values for even sizes).
double median(std::vector<double> v);

// Seeded random vectors and residuals of a solve (locus/kernels/solve/solve_accuracy.hpp).
using locus::random_vector;
using locus::relative_residual;

}  // namespace locus::cli
