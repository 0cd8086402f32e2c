// Full triangular solves with a supernodal factor (DESIGN.md "Numeric core" 5).
//
// solve():  x = A^{-1} b for one right-hand side, in original numbering, in place.
// solve8(): eight right-hand sides at once, row-interleaved (rhs[row*8 + lane],
//           one cache line per row), processed with xsimd batches. Fewer than 8
//           lanes are padded by the caller (use zeros), never a separate path.
// The permutation is applied inside. `work` (solve_work_size() doubles) may be
// passed to avoid allocating; solves are const on the factor and safe to run
// concurrently with other solves.
#pragma once
#include <span>
#include <vector>

#include "locus/kernels/factor/supernodal_factor.hpp"

namespace locus {

constexpr int kLanes = 8;

size_t solve_work_size(const NumericFactor& f, int lanes);
void solve(const NumericFactor& f, std::span<double> b, std::span<double> work = {});
void solve8(const NumericFactor& f, std::span<double> b8, std::span<double> work = {});

// In factor numbering: L y = b (forward) and L^T x = y (backward), in place.
// `tmp` holds max_super_rows (1 lane) or 8 * max_super_rows doubles.
void forward_full(const NumericFactor& f, double* x, double* tmp);
void backward_full(const NumericFactor& f, double* x, double* tmp);
void forward_full8(const NumericFactor& f, double* x8, double* tmp);
void backward_full8(const NumericFactor& f, double* x8, double* tmp);

// Per-supernode steps, shared with the sparse and subset solves (kernels/solve_*).
void forward_supernode(const NumericFactor& f, int32_t s, double* x, double* tmp);
void backward_supernode(const NumericFactor& f, int32_t s, double* x, double* tmp);
void forward_supernode8(const NumericFactor& f, int32_t s, double* x8, double* tmp);
void backward_supernode8(const NumericFactor& f, int32_t s, double* x8, double* tmp);

}  // namespace locus
