// Solve plans for localized solves (thesis §4.3, §3.6; DESIGN.md "Numeric core" 5).
//
// A right-hand side with support R touches, in the forward solve L y = b, only
// the supernodes on the etree paths from R to the root (the reach). The exact
// values of x = A^{-1} b at a wanted set W need, in the backward solve, only
// the supernodes of W and their ancestors. The approximate selective solve of
// thesis Algorithm 2 instead computes x only at a kept set K and treats every
// other entry as zero. A plan holds these supernode lists, ordered, computed
// once per (support, wanted/kept) pattern in time proportional to their size,
// and is reused for every right-hand side with that pattern. Forward and
// backward sets are independent: R and W may be disjoint (thesis §4.3).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/symbolic/symbolic_factor.hpp"

namespace locus {

struct SolvePlan {
  int32_t n = 0;
  HostVector<int32_t> rhs;       // support of b (original ids, as given)
  HostVector<int32_t> outputs;   // wanted (exact) or kept (approximate) ids, as given
  HostVector<int32_t> forward;   // supernodes, ascending
  HostVector<int32_t> backward;  // supernodes, descending
  HostVector<int32_t> touched;   // supernodes whose columns the solve reads or writes (forward ∪ backward), ascending
  bool approximate = false;
  // Approximate plans: kept factor columns, ascending (entries elsewhere are zero).
  HostVector<int32_t> kept_cols;
  // Approximate plans: the forward supernodes that are kept or have a kept
  // ancestor, ascending. The others only feed entries that Algorithm 2 sets to
  // zero, so a solver may skip them and still return the same kept values
  // (kernels/include/locus/kernels/solve/solve_selective.hpp); it must then read unkept entries as zero.
  HostVector<int32_t> forward_pruned;
  int64_t forward_columns = 0, backward_columns = 0;  // sizes, for reporting

  std::size_t num_outputs() const { return outputs.size(); }
};

// Exact plan: x at `wanted` equals the full solve's there.
SolvePlan plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                            std::span<const int32_t> wanted);
// Approximate plan (thesis Algorithm 2): x is computed at `kept` only, zero elsewhere.
SolvePlan plan_selective_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                               std::span<const int32_t> kept);

// Scratch of the planners: one mark per supernode, all zero between calls.
// Keeping it (and the plan) across queries makes planning cost proportional to
// the plan's size, not to the number of supernodes — small queries on a big
// mesh (single heat values, log-map patches, CVT cells) plan many times.
struct PlanWorkspace {
  HostVector<uint8_t> seen;
  HostVector<uint8_t> col_seen;  // one mark per factor column (approximate plans), zero between calls
  HostVector<uint64_t> bits;     // ascending order of large supernode sets (scratch)
};

// The same plans written into a caller-owned plan (its vectors' capacity is
// reused, so repeated planning does not allocate once warmed up).
void plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support, std::span<const int32_t> wanted,
                       SolvePlan& plan, PlanWorkspace& ws);
void plan_selective_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support, std::span<const int32_t> kept,
                          SolvePlan& plan, PlanWorkspace& ws);

// Supernode of every vertex (S.col_to_super[S.iperm[v]]), for the planner below:
// a region of 20k-200k scattered vertices then costs one random lookup per
// vertex instead of two.
HostVector<int32_t> vertex_supernodes(const SymbolicFactor& S);
// plan_subset_solve with that table (empty: the two lookups); the same plan.
void plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> vertex_super,
                       std::span<const int32_t> rhs_support, std::span<const int32_t> wanted, SolvePlan& plan,
                       PlanWorkspace& ws);
// Exact plan for a second solve over the vertices an exact plan `cover` already
// returned (same symbolic factor; e.g. the heat method's Poisson step over the
// heat step's region): when rhs_support and wanted are prefixes of
// cover.outputs, its forward and backward sets are both cover.backward (the
// ancestors of all of cover.outputs), found without walking the etree again;
// the backward set may then hold supernodes no wanted entry needs, which only
// costs their work, the wanted values are exact. Otherwise plan_subset_solve.
void plan_subset_solve_within(const SymbolicFactor& S, const SolvePlan& cover, std::span<const int32_t> rhs_support,
                              std::span<const int32_t> wanted, SolvePlan& plan, PlanWorkspace& ws);

// Memory an exact plan's solve reads from the factor, one right-hand-side
// pass each way (forward over plan.forward, backward over plan.backward): every
// supernode block of the pass (nrows x ncols values, 8 bytes each, the unused
// upper triangle of the diagonal block included: it shares the cache lines)
// and its row indices (4 bytes per row). `distinct_bytes` counts a supernode
// read by both passes once: the least a solve can move if nothing is in cache
// when it starts and nothing it reads is evicted before its second use.
// (Lanes' x rows are not counted: they are the solver's, not the factor's.)
struct PlanTraffic {
  int64_t forward_bytes = 0, backward_bytes = 0, distinct_bytes = 0;
  int64_t read_bytes() const { return forward_bytes + backward_bytes; }
};
PlanTraffic plan_traffic(const SymbolicFactor& S, const SolvePlan& plan);

}  // namespace locus
