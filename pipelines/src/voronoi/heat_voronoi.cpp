// Heat-diffusion Voronoi diagrams (pipelines/include/locus/pipelines/voronoi/heat_voronoi.hpp; thesis §3.4,
// eqs. 3.15-3.21, localized by §3.6 Algorithm 2).
#include "locus/pipelines/voronoi/heat_voronoi.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <string>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_selective.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/error.hpp"

namespace locus {

void check_surface_point(const Mesh& m, const SurfacePoint& p, const char* what, size_t index) {
  const std::string name = std::string(what) + " " + std::to_string(index);
  if (p.face < 0) {
    if (p.vertex < 0 || p.vertex >= m.num_vertices())
      fail(ErrorCode::BadUsage, name + " is vertex " + std::to_string(p.vertex) + ", but the mesh has " +
                                    std::to_string(m.num_vertices()) + " vertices");
    return;
  }
  if (p.face >= m.num_faces() || !m.is_triangle_mesh())
    fail(ErrorCode::BadUsage, name + " lies on face " + std::to_string(p.face) + ", but the mesh has " +
                                  std::to_string(m.num_faces()) + " triangles");
  double sum = 0;
  for (double b : p.bary) {
    if (!std::isfinite(b) || b < -1e-9)
      fail(ErrorCode::BadUsage, name + " has a barycentric weight that is negative or not finite");
    sum += b;
  }
  if (std::abs(sum - 1.0) > 1e-9) fail(ErrorCode::BadUsage, name + ": barycentric weights do not sum to 1");
}

std::array<double, 3> surface_point_position(const Mesh& m, const SurfacePoint& p) {
  if (p.face < 0) return {m.x[p.vertex], m.y[p.vertex], m.z[p.vertex]};
  const int32_t v[3] = {m.f0[p.face], m.f1[p.face], m.f2[p.face]};
  std::array<double, 3> r{0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    r[0] += p.bary[k] * m.x[v[k]];
    r[1] += p.bary[k] * m.y[v[k]];
    r[2] += p.bary[k] * m.z[v[k]];
  }
  return r;
}

int surface_point_support(const Mesh& m, const SurfacePoint& p, int32_t v[3], double w[3]) {
  if (p.face < 0) {
    v[0] = p.vertex;
    w[0] = 1.0;
    return 1;
  }
  const int32_t fv[3] = {m.f0[p.face], m.f1[p.face], m.f2[p.face]};
  int c = 0;
  for (int k = 0; k < 3; ++k)
    if (p.bary[k] > 0) {
      v[c] = fv[k];
      w[c++] = p.bary[k];
    }
  if (c == 0) {  // all weights within rounding of zero: the point is the first corner
    v[0] = fv[0];
    w[0] = 1.0;
    c = 1;
  }
  return c;
}

std::vector<SurfacePoint> random_surface_points(const Mesh& m, int32_t count, uint64_t seed) {
  const int32_t nf = m.num_faces();
  if (count < 0) fail(ErrorCode::BadUsage, "random surface points: negative count");
  if (nf == 0 || !m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": random points need a triangle mesh");
  std::vector<double> cum(nf);
  double acc = 0;
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t a = m.f0[f], b = m.f1[f], c = m.f2[f];
    const double u[3] = {m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]};
    const double v[3] = {m.x[c] - m.x[a], m.y[c] - m.y[a], m.z[c] - m.z[a]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    acc += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    cum[f] = acc;
  }
  uint64_t state = seed;
  auto next = [&state]() {  // splitmix64, uniform in [0, 1)
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  std::vector<SurfacePoint> out(count);
  for (int32_t i = 0; i < count; ++i) {
    const double r = next() * acc;
    const int32_t f = std::min<int32_t>(nf - 1, static_cast<int32_t>(std::upper_bound(cum.begin(), cum.end(), r) - cum.begin()));
    double s = next(), t = next();
    if (s + t > 1) {  // fold the unit square onto the triangle
      s = 1 - s;
      t = 1 - t;
    }
    out[i] = SurfacePoint{f, -1, {1 - s - t, s, t}};
  }
  return out;
}

HeatDiffusion prepare_heat_diffusion(const CscMatrix& A, std::vector<double> mass, double h, double t,
                                     const RunContext& ctx) {
  HeatDiffusion H;
  H.n = A.ncols;
  H.h = h;
  H.t = t;
  H.mass = std::move(mass);
  BatchStopwatch sw;
  const Ordering ord = order_matrix(A, {}, ctx);
  H.order_s = sw.lap();
  ctx.check_cancel();
  auto S = analyze(A, ord);
  H.analyze_s = sw.lap();
  ctx.check_cancel();
  H.factor = factorize(S, A, ctx);
  H.factor_s = sw.lap();
  return H;
}

HeatDiffusion prepare_heat_diffusion(const Mesh& m, double t_factor, double t_abs, const RunContext& ctx) {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  check_requirements(m, req);
  MeshDerived d = derive_mesh(m);
  d.checked = req;
  return prepare_heat_diffusion(m, d, t_factor, t_abs, ctx);
}

HeatDiffusion prepare_heat_diffusion(const Mesh& m, const MeshDerived& d, double t_factor, double t_abs,
                                     const RunContext& ctx) {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  if (!requirements_checked(d, req)) check_requirements(m, req);
  check_derived_of(d, m, "heat diffusion");
  if (m.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no vertices");
  if (!(t_abs >= 0) || !std::isfinite(t_abs) || (t_abs == 0 && (!(t_factor > 0) || !std::isfinite(t_factor))))
    fail(ErrorCode::BadUsage, "heat diffusion: the diffusion time must be a finite positive number");
  BatchStopwatch sw;
  const double h = d.h;
  const double t = t_abs > 0 ? t_abs : t_factor * h * h;
  const CscMatrix A = heat_operator(m, t);
  std::vector<double> mass = d.mass;
  const double op_s = sw.lap();
  HeatDiffusion H = prepare_heat_diffusion(A, std::move(mass), h, t, ctx);
  H.operator_s = op_s;
  return H;
}

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
  if (b.spos_.size() != static_cast<size_t>(n)) b.spos_.assign(n, -1);
  b.support_.clear();
  b.rhs_.clear();
  for (int l = 0; l < lanes; ++l)
    for (int32_t k = b.src_offsets[l]; k < b.src_offsets[l + 1]; ++k) {
      const int32_t v = b.src_vertex[k];
      if (v < 0 || v >= n) {
        for (int32_t u : b.support_) b.spos_[u] = -1;
        fail(ErrorCode::BadUsage, "heat batch: source vertex " + std::to_string(v) + " outside 0.." +
                                      std::to_string(n - 1));
      }
      if (b.spos_[v] < 0) {
        b.spos_[v] = static_cast<int32_t>(b.support_.size());
        b.support_.push_back(v);
        b.rhs_.resize(b.rhs_.size() + kLanes, 0.0);
      }
      b.rhs_[static_cast<size_t>(b.spos_[v]) * kLanes + l] += b.src_weight[k];
    }
  for (int32_t u : b.support_) b.spos_[u] = -1;
  plan_selective_solve(*H.factor.symbolic, b.support_, b.kept, b.plan_, b.pws_);
  b.values.resize(b.kept.size() * kLanes);
  solve_selective8(H.factor, b.plan_, b.rhs_, b.values, b.ws_);
}

namespace {

// (value desc, site asc): a total order, so top-K lists do not depend on merge order.
inline bool hotter(double v, int32_t s, double tv, int32_t ts) {
  return ts < 0 || v > tv || (v == tv && s < ts);
}

// Returns false (and changes nothing) when (s, v) is not hotter than the K-th entry.
inline bool insert_top(int32_t* ts, double* tv, int32_t s, double v) {
  if (!hotter(v, s, tv[kVoronoiTopK - 1], ts[kVoronoiTopK - 1])) return false;
  int i = kVoronoiTopK - 1;
  while (i > 0 && hotter(v, s, tv[i - 1], ts[i - 1])) {
    ts[i] = ts[i - 1];
    tv[i] = tv[i - 1];
    --i;
  }
  ts[i] = s;
  tv[i] = v;
  return true;
}

// One batch's contribution: per vertex its hottest min(lanes, K) (site, heat)
// pairs in the total order, so the serial merge stops at the first pair that
// does not enter a vertex's list (the rest are colder). Sorting the lanes happens
// in the parallel solve node.
struct VoronoiMsg {
  int lanes = 0;
  int per_vertex = 0;  // candidates per vertex: min(lanes, kVoronoiTopK)
  bool full = true;
  double solve_cpu_s = 0;    // thread CPU time of this batch's solve
  std::vector<int32_t> ids;  // local mode: vertex ids of the candidates
  std::vector<int32_t> cand_site;
  std::vector<double> cand_value;
};

}  // namespace

namespace {

// neighborhoods (per generator) or batch_kept (per batch) or neither (full solves).
HeatVoronoi heat_voronoi_impl(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                              std::span<const std::vector<int32_t>> neighborhoods,
                              std::span<const std::vector<int32_t>> batch_kept, std::span<const int32_t> batch_order,
                              const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  if (n != H.n) fail(ErrorCode::BadUsage, "heat voronoi: the operator was prepared for another mesh");
  if (sites.empty()) fail(ErrorCode::BadUsage, "heat voronoi: no generators");
  for (size_t i = 0; i < sites.size(); ++i) check_surface_point(m, sites[i], "generator", i);
  const bool local = !neighborhoods.empty() || !batch_kept.empty();
  if (!neighborhoods.empty() && neighborhoods.size() != sites.size())
    fail(ErrorCode::BadUsage, "heat voronoi: one neighborhood per generator expected");
  if (!batch_kept.empty() && batch_kept.size() != (sites.size() + kLanes - 1) / kLanes)
    fail(ErrorCode::BadUsage, "heat voronoi: one kept set per batch of 8 generators expected");
  std::vector<int32_t> order(sites.size());
  if (batch_order.empty()) {
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int32_t>(i);
  } else {
    if (batch_order.size() != sites.size()) fail(ErrorCode::BadUsage, "heat voronoi: batch order is not a permutation");
    order.assign(batch_order.begin(), batch_order.end());
  }
  const int32_t nb = static_cast<int32_t>((sites.size() + kLanes - 1) / kLanes);

  HeatVoronoi V;
  V.batches = nb;
  V.top_site.assign(static_cast<size_t>(n) * kVoronoiTopK, -1);
  V.top_value.assign(static_cast<size_t>(n) * kVoronoiTopK, 0.0);
  tbb::enumerable_thread_specific<HeatBatch> scratch;

  auto solve_batch = [&](int32_t b) {
    HeatBatch& hb = scratch.local();
    auto msg = std::make_shared<VoronoiMsg>();
    hb.clear_sources();
    hb.kept.clear();
    const int32_t first = b * kLanes;
    msg->lanes = std::min<int32_t>(kLanes, static_cast<int32_t>(sites.size()) - first);
    int32_t sites_of[kLanes];
    for (int l = 0; l < msg->lanes; ++l) {
      const int32_t s = order[first + l];
      sites_of[l] = s;
      int32_t v[3];
      double w[3];
      const int c = surface_point_support(m, sites[s], v, w);
      hb.add_source({v, static_cast<size_t>(c)}, {w, static_cast<size_t>(c)});
      if (!neighborhoods.empty()) hb.kept.insert(hb.kept.end(), neighborhoods[s].begin(), neighborhoods[s].end());
      if (local) hb.kept.insert(hb.kept.end(), v, v + c);
    }
    if (!batch_kept.empty()) hb.kept.insert(hb.kept.end(), batch_kept[b].begin(), batch_kept[b].end());
    if (local) {
      dedupe_kept(hb, n);  // first occurrences, in order: no sort needed by the plan
    }
    const double c0 = thread_cpu_seconds();
    solve_heat_batch(H, hb);
    msg->solve_cpu_s = thread_cpu_seconds() - c0;
    msg->full = !local;
    if (local) msg->ids = hb.kept;
    const int32_t cnt = hb.count();
    const int pv = std::min(msg->lanes, kVoronoiTopK);
    msg->per_vertex = pv;
    msg->cand_site.resize(static_cast<size_t>(cnt) * pv);
    msg->cand_value.resize(static_cast<size_t>(cnt) * pv);
    for (int32_t k = 0; k < cnt; ++k) {  // this batch's top pv per vertex (same total order)
      int32_t ts[kVoronoiTopK];
      double tv[kVoronoiTopK];
      std::fill(ts, ts + kVoronoiTopK, -1);
      std::fill(tv, tv + kVoronoiTopK, 0.0);
      for (int l = 0; l < msg->lanes; ++l) insert_top(ts, tv, sites_of[l], hb.values[static_cast<size_t>(k) * kLanes + l]);
      std::copy(ts, ts + pv, msg->cand_site.begin() + static_cast<size_t>(k) * pv);
      std::copy(tv, tv + pv, msg->cand_value.begin() + static_cast<size_t>(k) * pv);
    }
    return msg;
  };
  auto reduce = [&](const std::shared_ptr<VoronoiMsg>& msg) {
    const int pv = msg->per_vertex;
    const int32_t cnt = pv > 0 ? static_cast<int32_t>(msg->cand_site.size() / pv) : 0;
    V.solved_entries += cnt;
    V.solve_cpu_s += msg->solve_cpu_s;
    for (int32_t k = 0; k < cnt; ++k) {
      const int32_t v = msg->full ? k : msg->ids[k];
      int32_t* ts = V.top_site.data() + static_cast<size_t>(v) * kVoronoiTopK;
      double* tv = V.top_value.data() + static_cast<size_t>(v) * kVoronoiTopK;
      for (int i = 0; i < pv; ++i)
        if (!insert_top(ts, tv, msg->cand_site[static_cast<size_t>(k) * pv + i],
                        msg->cand_value[static_cast<size_t>(k) * pv + i]))
          break;  // the remaining candidates are colder
    }
  };
  run_batch_graph<VoronoiMsg>(ctx, nb, solve_batch, reduce, "heat voronoi");

  V.label.assign(n, -1);
  for (int32_t v = 0; v < n; ++v) V.label[v] = V.top_site[static_cast<size_t>(v) * kVoronoiTopK];
  // Breadth-first fallback for vertices no batch reached (localized mode only).
  const bool all_reached = std::find(V.label.begin(), V.label.end(), -1) == V.label.end();
  if (!all_reached) {
    std::vector<int32_t> queue;
    for (int32_t v = 0; v < n; ++v)
      if (V.label[v] >= 0) queue.push_back(v);
    const Adjacency adj = vertex_adjacency(m);
    for (size_t q = 0; q < queue.size(); ++q) {
      const int32_t v = queue[q];
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
        const int32_t w = adj.neighbors[p];
        if (V.label[w] < 0) {
          V.label[w] = V.label[v];
          ++V.unreached;
          queue.push_back(w);
        }
      }
    }
  }
  return V;
}

}  // namespace

HeatVoronoi heat_voronoi(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                         std::span<const std::vector<int32_t>> neighborhoods, std::span<const int32_t> batch_order,
                         const RunContext& ctx) {
  return heat_voronoi_impl(H, m, sites, neighborhoods, {}, batch_order, ctx);
}

HeatVoronoi heat_voronoi_batched(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                 std::span<const int32_t> batch_order,
                                 std::span<const std::vector<int32_t>> batch_kept, const RunContext& ctx) {
  if (batch_kept.empty()) fail(ErrorCode::BadUsage, "heat voronoi: no kept sets given");
  return heat_voronoi_impl(H, m, sites, {}, batch_kept, batch_order, ctx);
}

namespace {

struct MissingValue {
  int32_t site, vertex;
  double value;
};

}  // namespace

VoronoiDiagram extract_voronoi_diagram(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                       const HeatVoronoi& V, const RunContext& ctx) {
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  if (static_cast<int32_t>(V.label.size()) != n || n != H.n)
    fail(ErrorCode::BadUsage, "voronoi diagram: labels were computed for another mesh");
  VoronoiDiagram D;
  std::vector<MissingValue> missing;
  auto lookup = [&](int32_t v, int32_t s, bool& found) -> double {
    const int32_t* ts = V.top_site.data() + static_cast<size_t>(v) * kVoronoiTopK;
    for (int i = 0; i < kVoronoiTopK; ++i)
      if (ts[i] == s) {
        found = true;
        return V.top_value[static_cast<size_t>(v) * kVoronoiTopK + i];
      }
    auto it = std::lower_bound(missing.begin(), missing.end(), MissingValue{s, v, 0},
                               [](const MissingValue& a, const MissingValue& b) {
                                 return a.site != b.site ? a.site < b.site : a.vertex < b.vertex;
                               });
    if (it != missing.end() && it->site == s && it->vertex == v) {
      found = true;
      return it->value;
    }
    found = false;
    return 0.0;
  };
  // Pass 1: heat values of neighboring labels that no top-K list holds.
  std::vector<MissingValue> need;
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        if (a == b || V.label[v[a]] == V.label[v[b]]) continue;
        bool found = false;
        lookup(v[a], V.label[v[b]], found);
        if (!found) need.push_back({V.label[v[b]], v[a], 0});
      }
  }
  if (!need.empty()) {
    std::sort(need.begin(), need.end(), [](const MissingValue& a, const MissingValue& b) {
      return a.site != b.site ? a.site < b.site : a.vertex < b.vertex;
    });
    need.erase(std::unique(need.begin(), need.end(),
                           [](const MissingValue& a, const MissingValue& b) {
                             return a.site == b.site && a.vertex == b.vertex;
                           }),
               need.end());
    std::vector<int32_t> labels;
    for (const MissingValue& q : need)
      if (labels.empty() || labels.back() != q.site) labels.push_back(q.site);
    HeatBatch hb;
    size_t qpos = 0;
    for (size_t first = 0; first < labels.size(); first += kLanes) {
      ctx.check_cancel();
      const int lanes = static_cast<int>(std::min<size_t>(kLanes, labels.size() - first));
      hb.clear_sources();
      hb.kept.clear();
      for (int l = 0; l < lanes; ++l) {
        int32_t v[3];
        double w[3];
        const int c = surface_point_support(m, sites[labels[first + l]], v, w);
        hb.add_source({v, static_cast<size_t>(c)}, {w, static_cast<size_t>(c)});
      }
      solve_heat_batch(H, hb);
      for (; qpos < need.size() && (first + lanes == labels.size() || need[qpos].site < labels[first + lanes]); ++qpos) {
        const int l = static_cast<int>(std::lower_bound(labels.begin() + first, labels.begin() + first + lanes,
                                                        need[qpos].site) - labels.begin() - first);
        need[qpos].value = hb.values[static_cast<size_t>(need[qpos].vertex) * kLanes + l];
      }
    }
    D.resolved_missing = static_cast<int64_t>(need.size());
    missing.swap(need);
  }

  auto u = [&](int32_t v, int32_t s) {
    bool found = false;
    return lookup(v, s, found);
  };
  const EdgeIncidence inc = edge_incidence(m);
  std::vector<int32_t> edge_point(inc.edges.e0.size(), -1);
  auto add_point = [&](double x, double y, double z, int32_t sa, int32_t sb) {
    D.points.insert(D.points.end(), {x, y, z});
    D.point_edge_sites.insert(D.point_edge_sites.end(), {sa, sb});
    return static_cast<int32_t>(D.points.size() / 3 - 1);
  };
  // Point on edge (i, k) where the interpolants of l_i and l_k are equal (eqs. 3.19, 3.20).
  auto edge_pt = [&](int32_t f, int corner_i, int32_t i, int32_t k) {
    const int32_t e = inc.corner_edge[m.face_offsets[f] + corner_i];
    if (edge_point[e] >= 0) return edge_point[e];
    const int32_t a = V.label[i], b = V.label[k];
    const double den = u(i, a) - u(k, a) - u(i, b) + u(k, b);
    double beta = den > 0 ? (u(k, b) - u(k, a)) / den : 0.5;
    beta = std::clamp(beta, 0.0, 1.0);
    edge_point[e] = add_point(beta * m.x[i] + (1 - beta) * m.x[k], beta * m.y[i] + (1 - beta) * m.y[k],
                              beta * m.z[i] + (1 - beta) * m.z[k], std::min(a, b), std::max(a, b));
    return edge_point[e];
  };
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const int32_t l[3] = {V.label[v[0]], V.label[v[1]], V.label[v[2]]};
    if (l[0] == l[1] && l[1] == l[2]) continue;
    // Corner c's half-edge runs v[c] -> v[c+1].
    if (l[0] != l[1] && l[1] != l[2] && l[0] != l[2]) {
      const int32_t p01 = edge_pt(f, 0, v[0], v[1]), p12 = edge_pt(f, 1, v[1], v[2]), p20 = edge_pt(f, 2, v[2], v[0]);
      const double w0 = u(v[0], l[0]), w1 = u(v[1], l[1]), w2 = u(v[2], l[2]);
      const double ws = w0 + w1 + w2;
      const double c0 = ws > 0 ? w0 / ws : 1.0 / 3, c1 = ws > 0 ? w1 / ws : 1.0 / 3, c2 = ws > 0 ? w2 / ws : 1.0 / 3;
      const int32_t pc = add_point(c0 * m.x[v[0]] + c1 * m.x[v[1]] + c2 * m.x[v[2]],
                                   c0 * m.y[v[0]] + c1 * m.y[v[1]] + c2 * m.y[v[2]],
                                   c0 * m.z[v[0]] + c1 * m.z[v[1]] + c2 * m.z[v[2]], -1, -1);  // eq. 3.21
      ++D.corners;
      D.segments.insert(D.segments.end(), {pc, p01, pc, p12, pc, p20});
      continue;
    }
    // Two labels: the odd vertex k; the segment joins the points on its two edges.
    const int k = l[0] == l[1] ? 2 : (l[1] == l[2] ? 0 : 1);
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    // Edge (k, i) is corner k's half-edge, edge (j, k) is corner j's.
    const int32_t pa = edge_pt(f, k, v[k], v[i]);
    const int32_t pb = edge_pt(f, j, v[j], v[k]);
    D.segments.insert(D.segments.end(), {pa, pb});
  }

  // Chain segments into polylines through points of degree 2.
  const int32_t np = static_cast<int32_t>(D.points.size() / 3);
  const int32_t ns = static_cast<int32_t>(D.segments.size() / 2);
  std::vector<int32_t> deg(np + 1, 0);
  for (int32_t s = 0; s < ns; ++s) {
    ++deg[D.segments[2 * s] + 1];
    ++deg[D.segments[2 * s + 1] + 1];
  }
  std::vector<int32_t> off(deg);
  for (int32_t p = 0; p < np; ++p) off[p + 1] += off[p];
  std::vector<int32_t> inc_seg(2 * static_cast<size_t>(ns)), fill(off.begin(), off.end() - 1);
  for (int32_t s = 0; s < ns; ++s) {
    inc_seg[fill[D.segments[2 * s]]++] = s;
    inc_seg[fill[D.segments[2 * s + 1]]++] = s;
  }
  std::vector<uint8_t> used(ns, 0);
  auto walk = [&](int32_t start) {
    for (int32_t q = off[start]; q < off[start + 1]; ++q) {
      int32_t s = inc_seg[q];
      if (used[s]) continue;
      std::vector<int32_t> line{start};
      int32_t p = start;
      while (true) {
        used[s] = 1;
        p = D.segments[2 * s] == p ? D.segments[2 * s + 1] : D.segments[2 * s];
        line.push_back(p);
        if (off[p + 1] - off[p] != 2) break;
        const int32_t next = inc_seg[off[p]] == s ? inc_seg[off[p] + 1] : inc_seg[off[p]];
        if (used[next]) break;
        s = next;
      }
      D.polylines.push_back(std::move(line));
    }
  };
  for (int32_t p = 0; p < np; ++p)
    if (off[p + 1] - off[p] != 2) walk(p);
  for (int32_t p = 0; p < np; ++p) walk(p);  // closed loops
  return D;
}

}  // namespace locus
