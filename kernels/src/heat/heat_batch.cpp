// Batches of 8 heat sources, full or localized (kernels/include/locus/kernels/heat/heat_batch.hpp;
// thesis §3.6, Algorithm 2).
#include "locus/kernels/heat/heat_batch.hpp"

#include <string>

#include "locus/error.hpp"
#include "locus/kernels/solve/solve_selective.hpp"

namespace locus {

void dedupe_kept(HeatBatch& b, int32_t n) {
  if (b.mark_.size() != static_cast<size_t>(n)) b.mark_.assign(n, 0);
  size_t w = 0;
  for (size_t i = 0; i < b.kept.size(); ++i) {
    const int32_t v = b.kept[i];
    if (v < 0 || v >= n)
      fail(ErrorCode::BadUsage, "heat batch: neighborhood entry is vertex " + std::to_string(v) + ", outside 0.." +
                                    std::to_string(n - 1));
    if (!b.mark_[v]) {
      b.mark_[v] = 1;
      b.kept[w++] = v;
    }
  }
  b.kept.resize(w);
  for (int32_t v : b.kept) b.mark_[v] = 0;
}

std::span<int32_t> HeatBatch::vertex_map(int32_t n) {
  if (ws_.local.size() != static_cast<size_t>(n)) ws_.local.assign(n, -1);
  return {ws_.local.data(), ws_.local.size()};
}

void solve_heat_batch(const HeatDiffusion& H, HeatBatch& b) {
  const int32_t n = H.n;
  const int lanes = static_cast<int>(b.src_offsets.size()) - 1;
  if (lanes < 0 || lanes > kLanes) fail(ErrorCode::BadUsage, "heat batch: 0 to 8 sources per batch");
  b.n_ = n;
  b.full_ = b.kept.empty();
  if (b.full_) {
    b.values.assign(static_cast<size_t>(n) * kLanes, 0.0);
    for (int l = 0; l < lanes; ++l)
      for (int32_t k = b.src_offsets[l]; k < b.src_offsets[l + 1]; ++k)
        b.values[static_cast<size_t>(b.src_vertex[k]) * kLanes + l] += b.src_weight[k];
    const size_t ws = solve_work_size(H.factor, kLanes);
    if (b.work_.size() < ws) b.work_.resize(ws);
    solve8(H.factor, b.values, b.work_);
    return;
  }
  // Localized: the union support, one row of 8 right-hand side values per support vertex.
  // Support in order of first occurrence (the plan takes any order), found through a
  // position map instead of a sort: CVT centroid batches bring hundreds of sources.
  const std::span<int32_t> spos = b.vertex_map(n);  // the selective solve's row map, all -1 here
  b.support_.clear();
  b.rhs_.clear();
  for (int l = 0; l < lanes; ++l)
    for (int32_t k = b.src_offsets[l]; k < b.src_offsets[l + 1]; ++k) {
      const int32_t v = b.src_vertex[k];
      if (v < 0 || v >= n) {
        for (int32_t u : b.support_) spos[u] = -1;
        fail(ErrorCode::BadUsage, "heat batch: source vertex " + std::to_string(v) + " outside 0.." +
                                      std::to_string(n - 1));
      }
      if (spos[v] < 0) {
        spos[v] = static_cast<int32_t>(b.support_.size());
        b.support_.push_back(v);
        b.rhs_.resize(b.rhs_.size() + kLanes, 0.0);
      }
      b.rhs_[static_cast<size_t>(spos[v]) * kLanes + l] += b.src_weight[k];
    }
  for (int32_t u : b.support_) spos[u] = -1;
  plan_selective_solve(*H.factor.symbolic, b.support_, b.kept, b.plan_, b.pws_);
  b.values.resize(b.kept.size() * kLanes);
  solve_selective8(H.factor, b.plan_, b.rhs_, b.values, b.ws_);
}

}  // namespace locus
