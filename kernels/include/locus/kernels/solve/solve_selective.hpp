// The approximate selective solve of thesis Algorithm 2 (§3.6) with a pruned
// forward substitution, eight right-hand sides at once.
//
// Algorithm 2 keeps x only at a kept set K: y = L^{-1} b, y set to zero outside K,
// then L^T x = y restricted to K. Values of y outside K are never used, so the
// forward substitution only needs the supernodes of the reach that are kept or
// have a kept ancestor (SolvePlan::forward_pruned); the rest of the reach (the
// top separators of a nested-dissection factor, far from a local K) is skipped.
// Entries outside K are read as zero wherever the backward step reads them, so
// the kept values equal those of solve_planned8 (kernels/include/locus/kernels/solve/solve_sparse.hpp) up to
// rounding in a different BLAS/loop split, and the work scales with |K| and the
// kept part of the etree, not with the height of the whole factor.
//
// Uses the SolveWorkspace of solve_sparse (x zero between calls, keep zero
// between calls); cleans what it touched. Re-entrant with one workspace per thread.
// x is compact: the plan's touched columns get rows of x in ascending order
// (ws.local, an n-sized map), so a workspace holds touched x 8 doubles instead
// of n x 8 (27 MB per thread at 416k vertices); the arithmetic is unchanged.
#pragma once
#include <span>

#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"

namespace locus {

// plan: from plan_selective_solve. rhs[k * 8 + lane] is b at plan.rhs[k];
// out[k * 8 + lane] receives x at plan.outputs[k].
void solve_selective8(const NumericFactor& f, const SolvePlan& plan, std::span<const double> rhs,
                      std::span<double> out, SolveWorkspace& ws);

// Factor entries solve_selective8 reads for `plan` (forward: each pruned supernode's
// diagonal triangle and its rows down to the last needed one; backward: whole blocks
// of fully kept wide supernodes, else the kept columns' entries), counted by the same
// rules as the solver. `mark` is scratch of one byte per column, zero between calls.
// Compare with 2 * factor_entries(S), what a full forward + backward solve reads:
// the ratio bounds how much faster a local solve can be when reading the factor
// dominates.
int64_t selective_solve_reads(const SymbolicFactor& S, const SolvePlan& plan, std::vector<uint8_t>& mark);
// Stored lower-triangular entries of the factor: sum over supernodes of k(k+1)/2 + (m-k)k.
int64_t factor_entries(const SymbolicFactor& S);

}  // namespace locus
