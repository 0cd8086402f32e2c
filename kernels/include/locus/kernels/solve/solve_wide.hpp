// Exact subset solve with many right-hand sides in one pass over the factor
// (thesis §4.3; used by the log map, whose 7-22 heat sources share one plan).
//
// solve_planned8 (kernels/include/locus/kernels/solve/solve_sparse.hpp) handles 8 lanes; d sources then
// take ceil(d / 8) calls, and each call reads every supernode of the plan
// again. The backward columns of a log-map patch are hundreds of thousands of
// factor entries (megabytes, outside the caches), so those repeated reads are
// what the batches cost. Here one call carries up to kMaxWideLanes lanes: each
// supernode block is read once and applied to all lanes (register-blocked over
// four factor columns, no BLAS, so no per-call packing of the block).
//
// Rows are interleaved: rhs[k * lanes + l], out[k * lanes + l], lanes a
// multiple of 8 (pad unused lanes with zeros). Only exact plans
// (plan_subset_solve): out[k * lanes + l] equals the full solve of lane l at
// plan.outputs[k] up to rounding (the summation order differs from solve8).
//
// Working storage is compact: the plan's touched columns get local rows in
// ascending order (an n-sized index map plus touched x lanes doubles), so the
// cost and memory depend on the plan, not on n x lanes.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"

namespace locus {

constexpr int kMaxWideLanes = 32;

struct WideSolveWorkspace {
  HostVector<int32_t> local;     // n: local row of a touched factor column (stale elsewhere, never read)
  HostVector<double> x;          // touched columns x lanes (row r at x[r * lanes])
  HostVector<int32_t> rows;      // local rows below one supernode's diagonal block
  HostVector<int32_t> out_rows;  // after a solve: the row of x holding plan.outputs[k]
};

// `out` may be empty: the results then stay in ws.x (output k at row
// ws.out_rows[k], lanes contiguous), for callers that read them in x's row
// order (ascending factor columns: sequential) instead of gathering a copy.
void solve_planned_wide(const NumericFactor& f, const SolvePlan& plan, int lanes, std::span<const double> rhs,
                        std::span<double> out, WideSolveWorkspace& ws);

// One right-hand side (rhs[k] at plan.rhs[k]) with exactly the arithmetic of one
// lane of solve_planned_wide: the same numbers, bit for bit, as that lane of a
// wide solve of any width with this right-hand side in it (one source can be
// solved apart from its batch and still agree with it exactly). Results stay
// in ws.x, output k at row ws.out_rows[k].
void solve_planned_lane(const NumericFactor& f, const SolvePlan& plan, std::span<const double> rhs,
                        WideSolveWorkspace& ws);

}  // namespace locus
