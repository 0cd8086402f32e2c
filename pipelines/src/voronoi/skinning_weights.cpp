// Skinning weights from natural-neighbor coordinates (pipelines/include/locus/pipelines/voronoi/skinning_weights.hpp;
// thesis §3.7.2).
#include "locus/pipelines/voronoi/skinning_weights.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "locus/error.hpp"
#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/parallel/batch_graph.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"
#include "locus/pipelines/voronoi/skinning_refine.hpp"
#include "locus/pipelines/voronoi/skinning_sampled.hpp"

namespace locus {

namespace {

// Batches of 8 queries solved together on one pass over the factor (below).
constexpr int kGroupBatches = 3;
constexpr int kGroupLanes = kGroupBatches * kLanes;

struct SkinMsg {
  int32_t first = 0;
  int lanes = 0;
  NaturalCoordinates c[kGroupLanes];
};

struct SkinScratch {
  HostVector<double> x[kGroupBatches];  // n x 8 each, factor numbering
  HostVector<double> tmp;               // max_super_rows x 8
  HostVector<double> values;            // n x 8, vertex-major
  std::vector<uint8_t> in_reach;        // per supernode, zero between groups
  std::vector<int32_t> reach;
  NaturalScratch nn;
};

// Per-thread scratch kept across the calls of one skinning run (the refinement
// solves in rounds): no allocation and no page faults once warm.
using SkinScratchPool = tbb::enumerable_thread_specific<SkinScratch>;

// Up to 3 batches of 8 unit sources: batch g's heat at every vertex into s.x[g]
// (factor numbering), each with the full solve's per-supernode 8-lane arithmetic
// (kernels/solve/solve_full.hpp), so the values are the full solve's bit for bit.
// x is zero on entry (the caller zeroes it as it reads it out); the forward
// substitution runs over each batch's reach (the sources' etree paths,
// ascending), the backward one over every supernode, descending. The backward pass is what a row
// costs and reads the whole factor (megabytes, outside the caches): the batches
// take each supernode in turn while its block is in cache, one read for 24 lanes.
void solve_sources(const NumericFactor& F, std::span<const int32_t> sources, SkinScratch& s) {
  const SymbolicFactor& S = *F.symbolic;
  const int groups = static_cast<int>((sources.size() + kLanes - 1) / kLanes);
  const size_t nx = static_cast<size_t>(S.n) * kLanes;
  const size_t nt = static_cast<size_t>(S.max_super_rows) * kLanes;
  if (s.tmp.size() < nt) s.tmp.resize(nt);
  if (s.in_reach.size() < static_cast<size_t>(S.ns)) s.in_reach.assign(S.ns, 0);
  blas::SingleThreaded single;
  for (int g = 0; g < groups; ++g) {  // forward: each batch over its reach
    if (s.x[g].size() < nx) s.x[g].assign(nx, 0.0);
    double* x = s.x[g].data();
    const auto batch = sources.subspan(static_cast<size_t>(g) * kLanes,
                                       std::min<size_t>(kLanes, sources.size() - static_cast<size_t>(g) * kLanes));
    s.reach.clear();
    for (int32_t v : batch)
      for (int32_t sn = S.col_to_super[S.iperm[v]]; sn >= 0 && !(s.in_reach[sn] >> g & 1); sn = S.super_parent[sn]) {
        s.in_reach[sn] |= static_cast<uint8_t>(1u << g);
        s.reach.push_back(sn);
      }
    std::sort(s.reach.begin(), s.reach.end());
    for (size_t l = 0; l < batch.size(); ++l) x[static_cast<int64_t>(S.iperm[batch[l]]) * kLanes + l] = 1.0;
    for (int32_t sn : s.reach) forward_supernode8(F, sn, x, s.tmp.data());
  }
  for (int32_t sn = S.ns - 1; sn >= 0; --sn) {
    for (int g = 0; g < groups; ++g) backward_supernode8(F, sn, s.x[g].data(), s.tmp.data());
    s.in_reach[sn] = 0;
  }
}

// Exact rows of the vertices `query` (24 per task, in parallel) into rows
// (query.size() * k, row i for query[i]); degenerate[i] (when not empty) set
// where query[i]'s cell held no vertex (its row is an indicator); statistics into W.
void exact_rows(const NaturalNeighborField& F, const HeatDiffusion& H, const Mesh& m, std::span<const int32_t> query,
                std::span<double> rows, std::span<uint8_t> degenerate, SkinningWeights& W, SkinScratchPool& scratch,
                const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  const int32_t k = static_cast<int32_t>(F.sites.size());
  const int32_t count = static_cast<int32_t>(query.size());
  // Up to 3 batches per task, but at least 4 tasks per thread where the
  // refinement's fronts are small (the grouping changes no value: a batch is
  // the same 8 queries either way).
  const int threads = std::max(1, ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency());
  const int32_t batches = (count + kLanes - 1) / kLanes;
  const int32_t group_lanes = kLanes * std::clamp<int32_t>(batches / (4 * threads), 1, kGroupBatches);
  const int32_t nb = (count + group_lanes - 1) / group_lanes;
  const HostVector<int32_t>& perm = H.factor.symbolic->perm;
  auto solve_batch = [&](int32_t b) {
    SkinScratch& s = scratch.local();
    auto msg = std::make_shared<SkinMsg>();
    msg->first = b * group_lanes;
    msg->lanes = std::min(group_lanes, count - msg->first);
    solve_sources(H.factor, query.subspan(msg->first, msg->lanes), s);
    s.values.resize(static_cast<size_t>(n) * kLanes);
    for (int g = 0; g * kLanes < msg->lanes; ++g) {
      double* x = s.x[g].data();
      double* values = s.values.data();
      for (int32_t c = 0; c < n; ++c) {  // to vertex order, leaving x zero for the next group
        if (c + 16 < n) __builtin_prefetch(values + static_cast<size_t>(perm[c + 16]) * kLanes, 1);
        double* xv = x + static_cast<size_t>(c) * kLanes;
        double* out = values + static_cast<size_t>(perm[c]) * kLanes;
        for (int l = 0; l < kLanes; ++l) out[l] = xv[l];
        for (int l = 0; l < kLanes; ++l) xv[l] = 0.0;
      }
      const int lanes = std::min(kLanes, msg->lanes - g * kLanes);
      SurfacePoint q[kLanes];
      for (int l = 0; l < lanes; ++l) q[l] = vertex_point(query[msg->first + g * kLanes + l]);
      natural_neighbor_coordinates8(F, m, {q, static_cast<size_t>(lanes)}, s.values, s.nn,
                                    {msg->c + g * kLanes, static_cast<size_t>(lanes)});
    }
    return msg;
  };
  auto store = [&](const std::shared_ptr<SkinMsg>& msg) {  // per-vertex slots: arrival order is irrelevant
    for (int l = 0; l < msg->lanes; ++l) {
      const NaturalCoordinates& c = msg->c[l];
      std::copy(c.weight.begin(), c.weight.end(), rows.begin() + static_cast<size_t>(msg->first + l) * k);
      if (!degenerate.empty()) degenerate[msg->first + l] = c.degenerate;
      W.degenerate += c.degenerate;  // integer sums and a max: independent of arrival order
      W.fallback_faces += c.fallback_faces;
      W.max_clamped = std::max(W.max_clamped, c.clamped);
    }
  };
  run_batch_graph<SkinMsg>(ctx, nb, solve_batch, store, "skinning weights");
}

}  // namespace

SkinningWeights skinning_weights(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> handles,
                                 const RunContext& ctx) {
  BatchStopwatch sw;
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, handles, ctx);
  SkinningWeights W;
  W.prepare_s = sw.lap();
  const int32_t n = m.num_vertices();
  W.handles = static_cast<int32_t>(handles.size());
  W.method = "exact";
  W.samples = n;
  W.weight.assign(static_cast<size_t>(n) * W.handles, 0.0);
  std::vector<int32_t> all(n);
  for (int32_t v = 0; v < n; ++v) all[v] = v;
  SkinScratchPool scratch;
  exact_rows(F, H, m, all, W.weight, {}, W, scratch, ctx);
  W.weights_s = sw.lap();
  return W;
}

namespace {

// The greedy cover with the smallest radius (in rings) that has at most
// `target` samples: the first guess from the density of a regular triangulation
// (a cover of radius r edges leaves about one sample per 2 r^2 vertices), then
// wider until the count fits (a cover costs one pass over the vertex balls).
std::vector<int32_t> fitting_cover(const Adjacency& adj, std::span<const int32_t> first, int32_t n, int32_t target,
                                   int32_t& rings) {
  const double r = std::sqrt(static_cast<double>(n) / (2.0 * std::max(1, target)));
  rings = std::max(1, static_cast<int32_t>(std::floor(r)));
  std::vector<int32_t> samples = cover_samples(adj, first, rings);
  while (static_cast<int32_t>(samples.size()) > std::max(target, static_cast<int32_t>(first.size())) && rings < n) {
    ++rings;
    samples = cover_samples(adj, first, rings);
  }
  return samples;
}

// With refinement, a mesh of at most this many times the sample target takes exact
// rows everywhere: its cover holds a third of the vertices or more and the
// refinement about as many again, so the exact method costs about the same
// (cow, 2,904 vertices: 0.20 s against 0.19-0.32 s, factor included).
constexpr int32_t kExactBelowSamples = 3;
// The refinement's budget of exact rows times vertices (an exact row costs about
// one pass over the vertices): 2,884 rows on armadillo (26,002 vertices; armadillo
// 4 stops at 2,810, max |w - w_exact| 0.051, armadillo 7 at 2,330, 0.043;
// docs/skinning.md has the CLI's time against Blender's Automatic Weights),
// 7,676 on camel (9,770; with exact_up_to 0 camel stops at 2,800-2,950; by
// default it takes the small-mesh exact road).
constexpr double kRowWork = 7.5e7;
// Corners under this angle (degrees) take exact rows with the budget left
// (locus-bench skinning, with the zero-keeping at 0.03: camel 4 from 4 vertices
// off by more than 0.05 to 1, camel 7 from 0.045 to 0.035 max |w - w_exact|,
// about 340 and 300 more rows; as first seeds they took armadillo 7's budget,
// 0.043 -> 0.052).
constexpr double kSkinnyAngle = 10.0;

}  // namespace

SkinningWeights skinning_weights(const HeatDiffusion& H, const Mesh& m, std::span<const std::vector<int32_t>> handles,
                                 const SkinningOptions& options, const RunContext& ctx) {
  if (options.samples < 0) fail(ErrorCode::BadUsage, "skinning weights: samples must be >= 0");
  if (options.exact_up_to < 0) fail(ErrorCode::BadUsage, "skinning weights: exact_up_to must be >= 0");
  BatchStopwatch sw;
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, handles, ctx);
  SkinningWeights W;
  W.prepare_s = sw.lap();
  const int32_t n = m.num_vertices();
  const int32_t k = static_cast<int32_t>(handles.size());
  W.handles = k;
  W.weight.assign(static_cast<size_t>(n) * k, 0.0);
  std::vector<int32_t> owner(n, -1), handle_vertices;
  for (int32_t j = 0; j < k; ++j)
    for (int32_t v : handles[j]) {
      owner[v] = j;
      handle_vertices.push_back(v);
    }
  // Rows of handle vertices are their indicator; the others are solved.
  // indicator[i]: verts[i]'s row is an indicator for want of a cell (a handle
  // vertex, or a degenerate query), not because its cell touches one handle only.
  SkinScratchPool scratch;
  auto solve_rows = [&](std::span<const int32_t> verts, std::vector<double>& rows, std::vector<uint8_t>& indicator) {
    std::vector<int32_t> query;
    for (int32_t v : verts)
      if (owner[v] < 0) query.push_back(v);
    std::vector<double> qrows(query.size() * static_cast<size_t>(k));
    std::vector<uint8_t> qdeg(query.size(), 0);
    exact_rows(F, H, m, query, qrows, qdeg, W, scratch, ctx);
    rows.assign(verts.size() * static_cast<size_t>(k), 0.0);
    indicator.assign(verts.size(), 1);
    size_t qi = 0;
    for (size_t i = 0; i < verts.size(); ++i) {
      if (owner[verts[i]] >= 0) {
        rows[i * k + owner[verts[i]]] = 1.0;
      } else {
        indicator[i] = qdeg[qi];
        std::copy_n(qrows.begin() + qi++ * k, k, rows.begin() + i * k);
      }
    }
  };
  const int32_t target = options.samples > 0 ? options.samples : 1024;
  const Adjacency adj = vertex_adjacency(m);
  const bool small = options.refine_miss > 0 && (n <= options.exact_up_to ||
                                                  static_cast<int64_t>(n) <= static_cast<int64_t>(kExactBelowSamples) * target);
  if (options.method == SkinningMethod::Exact || small) {
    W.method = "exact";
    std::vector<int32_t> all;
    for (int32_t v = 0; v < n; ++v)  // the small-mesh road keeps the sampled road's NaN rows of vertices in no face
      if (!small || adj.offsets[v + 1] > adj.offsets[v]) all.push_back(v);
    std::vector<double> rows;
    std::vector<uint8_t> indicator;
    solve_rows(all, rows, indicator);
    if (small) std::fill(W.weight.begin(), W.weight.end(), std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < all.size(); ++i)
      std::copy_n(rows.begin() + i * k, k, W.weight.begin() + static_cast<size_t>(all[i]) * k);
    W.samples = static_cast<int32_t>(all.size());
    W.weights_s = sw.lap();
    return W;
  }
  W.method = "sampled";
  const std::vector<int32_t> samples =
      fitting_cover(adj, handle_vertices, n, target, W.sample_rings);
  W.samples = static_cast<int32_t>(samples.size());
  std::vector<double> rows;
  std::vector<uint8_t> indicator;
  solve_rows(samples, rows, indicator);
  W.weights_s = sw.lap();
  const Propagation P = propagate_samples(m, adj, samples, rows, indicator, k, W.weight, ctx, options.refine_miss);
  W.radius = P.radius;
  W.propagate_s = sw.lap();
  if (options.refine_miss > 0) {
    const int64_t budget = static_cast<int64_t>(kRowWork / n);
    const std::vector<int32_t> skinny = skinny_corners(m, kSkinnyAngle);
    refine_sampled_rows(adj, samples, rows, indicator, P.rough, skinny, owner, options.refine_miss, budget, solve_rows, W);
    W.samples += W.refined;
    W.weights_s += sw.lap();
  }
  return W;
}

}  // namespace locus
