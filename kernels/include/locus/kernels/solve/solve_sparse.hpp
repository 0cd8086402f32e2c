// Localized solves with a SolvePlan (thesis §3.6 Algorithm 2, §4.3):
// sparse forward substitution over the reach of the right-hand side, then the
// exact subset back substitution (wanted entries and their etree ancestors) or
// the approximate selective one (kept entries only, others zero).
//
// Cost depends on the plan, not on n: the caller-owned workspace holds a dense
// vector that is all zero between calls, and each call touches and cleans only
// the columns of the plan's supernodes. Exact plans return what the full solve
// returns at the wanted entries (same per-supernode arithmetic).
#pragma once
#include <span>
#include <vector>

#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"

namespace locus {

// In the host's memory (core/include/locus/core/host_allocator.hpp): n * 8 doubles per batch at 416k vertices.
struct SolveWorkspace {
  HostVector<double> x;        // n * lanes (solve_selective8: touched columns * 8), zero between calls
  HostVector<double> tmp;      // max_super_rows * lanes
  HostVector<uint8_t> keep;    // n, zero between calls
  // n, solve_selective8 only: row of x of a touched column during a call, -1
  // between calls, so that a caller may use it as its own n-entry map between
  // solves if it leaves it all -1 (HeatBatch::vertex_map: one such map per thread).
  HostVector<int32_t> local;
};

// rhs[k] is b at plan.rhs[k] (b is zero elsewhere); out[k] receives x at plan.outputs[k].
void solve_planned(const NumericFactor& f, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
                   SolveWorkspace& ws);
// Eight right-hand sides: rhs[k * 8 + lane], out[k * 8 + lane].
void solve_planned8(const NumericFactor& f, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
                    SolveWorkspace& ws);

// Forward substitution only, restricted to plan.forward: leaves y = L^{-1} b in
// ws.x (factor numbering) for callers that combine forward solves themselves
// (e.g. (A^{-1})_ij = (L^{-1} e_i) . (L^{-1} e_j)); clean with clear_workspace.
void forward_planned(const NumericFactor& f, const SolvePlan& plan, std::span<const double> rhs, SolveWorkspace& ws);
void clear_workspace(const NumericFactor& f, const SolvePlan& plan, SolveWorkspace& ws, int lanes);

}  // namespace locus
