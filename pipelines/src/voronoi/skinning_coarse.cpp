// Skinning weights on a coarse level of a large mesh, propagated to its vertices
// (pipelines/include/locus/pipelines/voronoi/skinning_coarse.hpp; thesis §3.7.2, §3.7.1).
#include "locus/pipelines/voronoi/skinning_coarse.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/pipelines/voronoi/restricted_dual.hpp"
#include "locus/pipelines/voronoi/site_neighborhoods.hpp"
#include "locus/pipelines/voronoi/skinning_sampled.hpp"

namespace locus {

bool skinning_uses_coarse_level(int32_t n, const SkinningOptions& options) {
  return options.method == SkinningMethod::Sampled && n > 4 * kSkinCoarseVertices;
}

namespace {

struct CoarseLevel {
  Mesh mesh;                     // the dual; vertex i sits at fine vertex fine_of[i]
  std::vector<int32_t> fine_of;  // coarse vertex -> fine vertex
  std::vector<int32_t> label;    // fine vertex -> coarse vertex of its cell
};

// The cover with the smallest radius (in rings) within the budget: a cover of
// radius r leaves about one site per 2 r^2 vertices on a regular triangulation.
std::vector<int32_t> coarse_cover(const Adjacency& adj, std::span<const int32_t> first, int32_t n) {
  int32_t rings = std::max(1, static_cast<int32_t>(std::floor(std::sqrt(n / (2.0 * kSkinCoarseVertices)))));
  std::vector<int32_t> sites = cover_samples(adj, first, rings);
  while (static_cast<int32_t>(sites.size()) > std::max<int32_t>(kSkinCoarseVertices, first.size()) && rings < n)
    sites = cover_samples(adj, first, ++rings);
  return sites;
}

// Sites at the cover's vertices, graph-geodesic cells, sites added at the
// dual's defects until it is a manifold (at worst every vertex is a site: the
// dual is then the mesh itself), and the dual as a mesh.
CoarseLevel coarse_level(const Mesh& m, const Adjacency& adj, std::span<const int32_t> handle_vertices,
                         const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  std::vector<SurfacePoint> sites;
  std::vector<uint8_t> is_site(n, 0);
  for (int32_t v : coarse_cover(adj, handle_vertices, n)) {
    sites.push_back(vertex_point(v));
    is_site[v] = 1;
  }
  const DualTopology topo = dual_topology(m);
  HostVector<int32_t> g;
  RestrictedDual dual;
  for (int32_t round = 0;; ++round) {
    ctx.check_cancel();
    g = geodesic_site_cells(m, adj, sites);
    for (int32_t v = 0; v < n; ++v)
      if (g[v] < 0) fail(ErrorCode::Numerical, "skinning coarse level: vertex " + std::to_string(v) + " has no cell");
    dual = restricted_dual(m, topo, std::span<const int32_t>(g.data(), g.size()), sites);
    if (dual.defects.total() == 0) break;
    int32_t added = 0;
    for (int32_t v : dual.repair_vertices)
      if (!is_site[v]) {
        is_site[v] = 1;
        sites.push_back(vertex_point(v));
        ++added;
      }
    if (added == 0 || round > n)
      fail(ErrorCode::Numerical, "skinning coarse level: the cells' dual keeps " +
                                     std::to_string(dual.defects.total()) + " defects");
  }
  CoarseLevel L;
  std::vector<int32_t> vertex_site;
  L.mesh = dual_mesh(m, dual, sites, vertex_site);
  std::vector<int32_t> coarse_of_site(sites.size(), -1);
  for (size_t i = 0; i < vertex_site.size(); ++i) {
    const int32_t s = vertex_site[i];
    coarse_of_site[s] = static_cast<int32_t>(i);
    const int32_t bv = dual.boundary_vertex.empty() ? -1 : dual.boundary_vertex[s];
    L.fine_of.push_back(bv >= 0 ? bv : sites[s].vertex);
  }
  L.label.resize(n);
  for (int32_t v = 0; v < n; ++v) L.label[v] = coarse_of_site[g[v]];
  return L;
}

// Barycentric coordinates of p's projection onto triangle (a, b, c) and p's
// distance from its plane; false for a degenerate triangle.
bool project(const std::array<double, 3>& p, const std::array<double, 3>* t, double lambda[3], double& height) {
  double e1[3], e2[3], d[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = t[1][i] - t[0][i];
    e2[i] = t[2][i] - t[0][i];
    d[i] = p[i] - t[0][i];
  }
  const double a11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
  const double a12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
  const double a22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
  const double b1 = d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2];
  const double b2 = d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2];
  const double det = a11 * a22 - a12 * a12;
  if (!(det > 1e-20 * a11 * a22)) return false;
  const double u = (a22 * b1 - a12 * b2) / det, w = (a11 * b2 - a12 * b1) / det;
  lambda[0] = 1 - u - w;
  lambda[1] = u;
  lambda[2] = w;
  double h2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double r = d[i] - u * e1[i] - w * e2[i];
    h2 += r * r;
  }
  height = std::sqrt(h2);
  return true;
}

struct Propagator {
  const Mesh& m;
  const Adjacency& adj;
  const CoarseLevel& L;
  std::span<const double> coarse;  // coarse rows
  int32_t k;
  std::vector<int64_t> vf_off;  // coarse vertex -> incident coarse triangles
  std::vector<int32_t> vf;

  Propagator(const Mesh& fm, const Adjacency& a, const CoarseLevel& level, std::span<const double> rows, int32_t handles)
      : m(fm), adj(a), L(level), coarse(rows), k(handles) {
    const Mesh& c = L.mesh;
    const int32_t nc = c.num_vertices(), nf = c.num_faces();
    vf_off.assign(static_cast<size_t>(nc) + 1, 0);
    for (int32_t f = 0; f < nf; ++f)
      for (int32_t v : {c.f0[f], c.f1[f], c.f2[f]}) ++vf_off[v + 1];
    for (int32_t v = 0; v < nc; ++v) vf_off[v + 1] += vf_off[v];
    vf.resize(vf_off[nc]);
    std::vector<int64_t> fill(vf_off.begin(), vf_off.end() - 1);
    for (int32_t f = 0; f < nf; ++f)
      for (int32_t v : {c.f0[f], c.f1[f], c.f2[f]}) vf[fill[v]++] = f;
  }

  // Fine vertex v's row: among the coarse triangles around the cells of v and
  // its neighbours, the nearest one v projects into (coordinates >= -1e-9),
  // else the one it is least outside; coordinates clamped and renormalized.
  void row(int32_t v, std::vector<int32_t>& cells, double* o) const {
    const Mesh& c = L.mesh;
    const std::array<double, 3> p{m.x[v], m.y[v], m.z[v]};
    cells.assign(1, L.label[v]);
    for (int64_t q = adj.offsets[v]; q < adj.offsets[v + 1]; ++q) {
      const int32_t l = L.label[adj.neighbors[q]];
      if (std::find(cells.begin(), cells.end(), l) == cells.end()) cells.push_back(l);
    }
    int32_t best = -1;
    double best_lambda[3] = {1, 0, 0}, best_min = -std::numeric_limits<double>::infinity();
    double best_height = std::numeric_limits<double>::infinity();
    for (int32_t cell : cells)
      for (int64_t q = vf_off[cell]; q < vf_off[cell + 1]; ++q) {
        const int32_t f = vf[q];
        const int32_t corner[3] = {c.f0[f], c.f1[f], c.f2[f]};
        std::array<double, 3> t[3];
        for (int i = 0; i < 3; ++i) t[i] = {c.x[corner[i]], c.y[corner[i]], c.z[corner[i]]};
        double lambda[3], height = 0;
        if (!project(p, t, lambda, height)) continue;
        const double lo = std::min({lambda[0], lambda[1], lambda[2]});
        const bool inside = lo >= -1e-9, best_inside = best_min >= -1e-9;
        const bool better = inside ? (!best_inside || height < best_height) : (!best_inside && lo > best_min);
        if (better) {
          best = f;
          best_min = lo;
          best_height = height;
          std::copy_n(lambda, 3, best_lambda);
        }
      }
    std::fill(o, o + k, 0.0);
    if (best < 0) {  // no usable triangle: the row of v's cell
      std::copy_n(coarse.data() + static_cast<size_t>(L.label[v]) * k, k, o);
      return;
    }
    const int32_t corner[3] = {c.f0[best], c.f1[best], c.f2[best]};
    double sum = 0;
    for (double& l : best_lambda) {
      l = std::max(l, 0.0);
      sum += l;
    }
    for (int i = 0; i < 3; ++i) {
      const double* w = coarse.data() + static_cast<size_t>(corner[i]) * k;
      for (int32_t j = 0; j < k; ++j) o[j] += best_lambda[i] / sum * w[j];
    }
    double total = 0;
    for (int32_t j = 0; j < k; ++j) total += o[j];
    for (int32_t j = 0; j < k; ++j) o[j] /= total;
  }
};

}  // namespace

SkinningWeights skinning_weights_coarse(const Mesh& m, std::span<const std::vector<int32_t>> handles,
                                        const SkinningOptions& options, double t_factor, double t_abs,
                                        const RunContext& ctx) {
  if (options.samples < 0) fail(ErrorCode::BadUsage, "skinning weights: samples must be >= 0");
  BatchStopwatch sw;
  const int32_t n = m.num_vertices();
  const int32_t k = static_cast<int32_t>(handles.size());
  std::vector<int32_t> owner(n, -1), handle_vertices;
  for (int32_t j = 0; j < k; ++j)
    for (int32_t v : handles[j]) {
      owner[v] = j;
      handle_vertices.push_back(v);
    }
  const Adjacency adj = vertex_adjacency(m);
  const CoarseLevel L = coarse_level(m, adj, handle_vertices, ctx);
  const int32_t nc = L.mesh.num_vertices();
  // The handles on the coarse level: the coarse vertices at their vertices
  // (every handle vertex is a site; a boundary cell's vertex may have moved).
  std::vector<int32_t> coarse_at(n, -1);
  for (int32_t i = 0; i < nc; ++i) coarse_at[L.fine_of[i]] = i;
  std::vector<std::vector<int32_t>> coarse_handles(k);
  for (int32_t j = 0; j < k; ++j) {
    for (int32_t v : handles[j]) {
      const int32_t c = coarse_at[v] >= 0 ? coarse_at[v] : L.label[v];
      auto& h = coarse_handles[j];
      if (std::find(h.begin(), h.end(), c) == h.end()) h.push_back(c);
    }
    for (int32_t i = 0; i < j; ++i)
      for (int32_t c : coarse_handles[j])
        if (std::find(coarse_handles[i].begin(), coarse_handles[i].end(), c) != coarse_handles[i].end())
          fail(ErrorCode::BadUsage, "skinning weights: handles " + std::to_string(i) + " and " + std::to_string(j) +
                                        " meet on the coarse level");
  }
  const double level_s = sw.lap();
  const HeatDiffusion Hc = prepare_heat_diffusion(L.mesh, t_factor, t_abs, ctx);
  SkinningWeights W;
  W.factor_s = sw.lap();
  SkinningOptions co = options;
  co.refine_miss = 0;  // the coarse level's error is its discretization's: no refinement (docs/skinning.md)
  co.method = SkinningMethod::Sampled;
  const SkinningWeights C = skinning_weights(Hc, L.mesh, coarse_handles, co, ctx);
  W.handles = k;
  W.method = "coarse";
  W.samples = C.samples;
  W.sample_rings = C.sample_rings;
  W.radius = C.radius;
  W.coarse_vertices = nc;
  W.degenerate = C.degenerate;
  W.fallback_faces = C.fallback_faces;
  W.max_clamped = C.max_clamped;
  W.t = Hc.t;
  W.prepare_s = level_s + C.prepare_s;
  W.weights_s = C.weights_s + C.propagate_s;
  sw.lap();
  ctx.check_cancel();
  W.weight.assign(static_cast<size_t>(n) * k, 0.0);
  const Propagator P(m, adj, L, C.weight, k);
  const int threads = std::max(1, ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency());
  run_with_threads(threads, [&] {
    tbb::parallel_for(tbb::blocked_range<int32_t>(0, n, 1024), [&](const tbb::blocked_range<int32_t>& r) {
      std::vector<int32_t> cells;
      for (int32_t v = r.begin(); v < r.end(); ++v) {
        double* o = W.weight.data() + static_cast<size_t>(v) * k;
        if (owner[v] >= 0) {
          o[owner[v]] = 1.0;
        } else if (coarse_at[v] >= 0) {
          std::copy_n(C.weight.data() + static_cast<size_t>(coarse_at[v]) * k, k, o);
        } else {
          P.row(v, cells, o);
        }
      }
    });
  });
  W.propagate_s = sw.lap();
  return W;
}

}  // namespace locus
