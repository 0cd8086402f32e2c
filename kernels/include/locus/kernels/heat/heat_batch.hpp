// Batches of up to 8 heat sources on a prepared heat operator (heat_diffusion.hpp):
// u = (M - t L_C)^{-1} b for 8 right-hand sides at once (8-lane solves), in full or,
// localized (thesis §3.6, Algorithm 2), by the approximate selective solve on a
// kept vertex set (kernels/solve/solve_selective: the forward substitution skips
// the part of the etree that only feeds zeroed entries).
// Thread safety: one HeatBatch per thread (it is scratch); the operator is shared.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/solve/solve_full.hpp"  // kLanes
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"

namespace locus {

// One batch of up to 8 heat sources, solved in full (kept empty) or by the
// approximate selective solve on `kept` (unique vertex ids, any order). Inputs:
// lane l's source is src_vertex/src_weight[src_offsets[l] .. src_offsets[l+1]);
// lanes beyond src_offsets.size()-1 are zero. Output: values[k * kLanes + lane] at
// vertex id(k), k < count(). The private part is reusable scratch.
class HeatBatch {
 public:
  std::vector<int32_t> src_offsets{0};
  HostVector<int32_t> src_vertex;
  HostVector<double> src_weight;
  HostVector<int32_t> kept;
  HostVector<double> values;  // in the host's memory (host_allocator.hpp)

  int32_t count() const { return full_ ? n_ : static_cast<int32_t>(kept.size()); }
  int32_t id(int32_t k) const { return full_ ? k : kept[k]; }
  void clear_sources() { src_offsets.assign(1, 0); src_vertex.clear(); src_weight.clear(); }
  void add_source(std::span<const int32_t> v, std::span<const double> w) {
    src_vertex.insert(src_vertex.end(), v.begin(), v.end());
    src_weight.insert(src_weight.end(), w.begin(), w.end());
    src_offsets.push_back(static_cast<int32_t>(src_vertex.size()));
  }
  // The selective-solve plan of the last localized solve (kept non-empty), e.g. to
  // count the factor entries it read (solve_selective.hpp selective_solve_reads).
  const SolvePlan& plan() const { return plan_; }
  // An n-entry map, all -1 between uses, that a caller may use between solves
  // if it leaves it all -1 again (e.g. a vertex's slot or position in a list).
  // The batch's own source positions and the selective solve's rows use the
  // same array, one after the other: one n-vector per batch instead of three
  // (at 416k vertices 1.7 MB each, per thread).
  std::span<int32_t> vertex_map(int32_t n);

 private:
  friend void solve_heat_batch(const HeatDiffusion& H, HeatBatch& b);
  friend void dedupe_kept(HeatBatch& b, int32_t n);

  bool full_ = true;
  int32_t n_ = 0;
  SolveWorkspace ws_;
  SolvePlan plan_;      // reused: planning does not allocate once warm
  PlanWorkspace pws_;
  HostVector<double> work_, rhs_;
  HostVector<int32_t> support_;
  HostVector<uint8_t> mark_;  // n, zero between uses
  // (vertex_map: ws_.local, n, -1 between uses) the position of a source vertex in support_
};
// Solves b's sources on H (full when b.kept is empty, else selective on b.kept).
void solve_heat_batch(const HeatDiffusion& H, HeatBatch& b);
// Removes repeated ids from b.kept, keeping first occurrences in order (O(|kept|),
// no sort); throws BadUsage for ids outside 0..n-1.
void dedupe_kept(HeatBatch& b, int32_t n);

}  // namespace locus
