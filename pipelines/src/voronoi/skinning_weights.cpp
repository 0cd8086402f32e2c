// Skinning weights from natural-neighbor coordinates (pipelines/include/locus/pipelines/voronoi/skinning_weights.hpp;
// thesis §3.7.2).
#include "locus/pipelines/voronoi/skinning_weights.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/parallel/batch_graph.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"
#include "locus/pipelines/voronoi/skinning_sampled.hpp"

namespace locus {

namespace {

struct SkinMsg {
  int32_t first = 0;
  int lanes = 0;
  NaturalCoordinates c[kLanes];
};

struct SkinScratch {
  HeatBatch batch;
  std::vector<double> lane;
  NaturalScratch nn;
};

// Exact rows of the vertices `query` (8 per solve, in parallel) into rows
// (query.size() * k, row i for query[i]); statistics into W.
void exact_rows(const NaturalNeighborField& F, const HeatDiffusion& H, const Mesh& m, std::span<const int32_t> query,
                std::span<double> rows, SkinningWeights& W, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  const int32_t k = static_cast<int32_t>(F.sites.size());
  const int32_t count = static_cast<int32_t>(query.size());
  const int32_t nb = (count + kLanes - 1) / kLanes;
  tbb::enumerable_thread_specific<SkinScratch> scratch;
  auto solve_batch = [&](int32_t b) {
    SkinScratch& s = scratch.local();
    auto msg = std::make_shared<SkinMsg>();
    msg->first = b * kLanes;
    msg->lanes = std::min(kLanes, count - msg->first);
    s.batch.clear_sources();
    s.batch.kept.clear();
    for (int l = 0; l < msg->lanes; ++l) {
      const int32_t v = query[msg->first + l];
      const double one = 1.0;
      s.batch.add_source({&v, 1}, {&one, 1});
    }
    solve_heat_batch(H, s.batch);
    s.lane.resize(n);
    for (int l = 0; l < msg->lanes; ++l) {
      for (int32_t v = 0; v < n; ++v) s.lane[v] = s.batch.values[static_cast<size_t>(v) * kLanes + l];
      msg->c[l] = natural_neighbor_coordinates(F, m, vertex_point(query[msg->first + l]), s.lane, s.nn);
    }
    return msg;
  };
  auto store = [&](const std::shared_ptr<SkinMsg>& msg) {  // per-vertex slots: arrival order is irrelevant
    for (int l = 0; l < msg->lanes; ++l) {
      const NaturalCoordinates& c = msg->c[l];
      std::copy(c.weight.begin(), c.weight.end(), rows.begin() + static_cast<size_t>(msg->first + l) * k);
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
  exact_rows(F, H, m, all, W.weight, W, ctx);
  W.weights_s = sw.lap();
  return W;
}

namespace {

// Default cover radius: about `samples` greedy-cover samples (a cover of radius r
// edges leaves roughly one sample per 2 r^2 vertices on a regular triangulation).
int32_t cover_rings(int32_t n, int32_t samples) {
  const double r = std::sqrt(static_cast<double>(n) / (2.0 * std::max(1, samples)));
  return std::max(1, static_cast<int32_t>(std::floor(r)));
}

// Appends to `samples` the vertices within `rings` edges of a handle vertex that
// are not samples yet (breadth-first, ascending ids per ring: deterministic).
void append_near_handles(const Adjacency& adj, std::span<const int32_t> handle_vertices, int32_t rings,
                         std::vector<int32_t>& samples) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1;
  std::vector<int32_t> depth(n, -1);
  std::vector<uint8_t> is_sample(n, 0);
  for (int32_t v : samples) is_sample[v] = 1;
  std::vector<int32_t> queue(handle_vertices.begin(), handle_vertices.end());
  for (int32_t v : queue) depth[v] = 0;
  for (size_t q = 0; q < queue.size(); ++q) {
    const int32_t v = queue[q];
    if (!is_sample[v]) {
      is_sample[v] = 1;
      samples.push_back(v);
    }
    if (depth[v] == rings) continue;
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
      const int32_t w = adj.neighbors[p];
      if (depth[w] < 0) {
        depth[w] = depth[v] + 1;
        queue.push_back(w);
      }
    }
  }
}

constexpr int kRefinePasses = 6;
constexpr double kRoughJump = 0.03;

// Non-exact vertices whose row differs from a neighbour's by more than
// kRoughJump in a weight, or has a zero where the neighbour's is not (or the
// reverse), ascending.
std::vector<int32_t> rough_vertices(const Adjacency& adj, std::span<const double> w, int32_t k,
                                    std::span<const uint8_t> exact) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1;
  std::vector<int32_t> out;
  for (int32_t v = 0; v < n; ++v) {
    if (exact[v]) continue;
    bool rough = false;
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1] && !rough; ++p) {
      const int32_t u = adj.neighbors[p];
      for (int32_t j = 0; j < k && !rough; ++j) {
        const double a = w[static_cast<size_t>(v) * k + j], b = w[static_cast<size_t>(u) * k + j];
        rough = std::abs(a - b) > kRoughJump || ((a == 0) != (b == 0));
      }
    }
    if (rough) out.push_back(v);
  }
  return out;
}

}  // namespace

SkinningWeights skinning_weights(const HeatDiffusion& H, const Mesh& m, std::span<const std::vector<int32_t>> handles,
                                 const SkinningOptions& options, const RunContext& ctx) {
  if (options.samples < 0) fail(ErrorCode::BadUsage, "skinning weights: samples must be >= 0");
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
  auto solve_rows = [&](std::span<const int32_t> verts, std::vector<double>& rows) {
    std::vector<int32_t> query;
    for (int32_t v : verts)
      if (owner[v] < 0) query.push_back(v);
    std::vector<double> qrows(query.size() * static_cast<size_t>(k));
    exact_rows(F, H, m, query, qrows, W, ctx);
    rows.assign(verts.size() * static_cast<size_t>(k), 0.0);
    size_t qi = 0;
    for (size_t i = 0; i < verts.size(); ++i) {
      if (owner[verts[i]] >= 0) {
        rows[i * k + owner[verts[i]]] = 1.0;
      } else {
        std::copy_n(qrows.begin() + qi++ * k, k, rows.begin() + i * k);
      }
    }
  };
  if (options.method == SkinningMethod::Exact) {
    W.method = "exact";
    std::vector<int32_t> all(n);
    for (int32_t v = 0; v < n; ++v) all[v] = v;
    solve_rows(all, W.weight);
    W.samples = n;
    W.weights_s = sw.lap();
    return W;
  }
  W.method = "sampled";
  const Adjacency adj = vertex_adjacency(m);
  W.sample_rings = cover_rings(n, options.samples > 0 ? options.samples : 1024);
  // The weights are steepest next to a handle (a cone at the site, steeper than
  // any propagation resolves): the vertices within 2 rings + 2 edges of a handle
  // get exact rows too.
  std::vector<int32_t> samples = cover_samples(adj, handle_vertices, W.sample_rings);
  append_near_handles(adj, handle_vertices, 2 * W.sample_rings + 2, samples);
  W.samples = static_cast<int32_t>(samples.size());
  std::vector<double> rows;
  solve_rows(samples, rows);
  W.weights_s = sw.lap();
  const Propagation P = propagate_samples(m, adj, samples, rows, k, W.weight, ctx);
  W.radius = P.radius;
  // Refinement: where the propagated weights jump between neighbours (steeper
  // than the samples resolve) or a weight is zero next to a nonzero one (the
  // support border, widened by the propagation), the vertices get exact rows;
  // repeated while new such vertices appear, a few passes at most.
  std::vector<uint8_t> exact(n, 0);
  for (int32_t v : samples) exact[v] = 1;
  for (int pass = 0; pass < kRefinePasses; ++pass) {
    const std::vector<int32_t> todo = rough_vertices(adj, W.weight, k, exact);
    if (todo.empty()) break;
    std::vector<double> more;
    solve_rows(todo, more);
    for (size_t i = 0; i < todo.size(); ++i) {
      std::copy_n(more.begin() + i * k, k, W.weight.begin() + static_cast<size_t>(todo[i]) * k);
      exact[todo[i]] = 1;
    }
    W.samples += static_cast<int32_t>(todo.size());
  }
  W.propagate_s = sw.lap();
  return W;
}

}  // namespace locus
