// Heat-diffusion Voronoi diagrams (pipelines/include/locus/pipelines/voronoi/heat_voronoi.hpp; thesis §3.4,
// eqs. 3.15-3.21, localized by §3.6 Algorithm 2).
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "locus/core/release_free_memory.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <memory>
#include <string>

#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/parallel/batch_graph.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

// (value desc, site asc): a total order, so top-K lists do not depend on merge order.
inline bool hotter(double v, int32_t s, double tv, int32_t ts) {
  return ts < 0 || v > tv || (v == tv && s < ts);
}

// Returns false (and changes nothing) when (s, v) is not hotter than the K-th entry.
template <int K = kVoronoiTopK>
inline bool insert_top(int32_t* ts, double* tv, int32_t s, double v) {
  if (!hotter(v, s, tv[K - 1], ts[K - 1])) return false;
  int i = K - 1;
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
  int per_vertex = 0;  // candidates per vertex: min(lanes, V.top_k)
  bool full = true;
  double solve_cpu_s = 0;    // thread CPU time of this batch's solve
  // Per-batch buffers in the host's memory (core/include/locus/core/host_allocator.hpp).
  HostVector<int32_t> ids;  // local mode: vertex ids of the candidates
  HostVector<int32_t> cand_site;
  HostVector<double> cand_value;
};

}  // namespace

namespace {

// The generators in batch order: batch_order, or the identity when it is empty.
std::vector<int32_t> generator_order(size_t count, std::span<const int32_t> batch_order) {
  std::vector<int32_t> order(count);
  if (batch_order.empty()) {
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int32_t>(i);
  } else {
    if (batch_order.size() != count) fail(ErrorCode::BadUsage, "heat voronoi: batch order is not a permutation");
    order.assign(batch_order.begin(), batch_order.end());
  }
  return order;
}

// Labels from the merged top-K lists (eq. 3.18), then the breadth-first fallback
// for vertices no batch reached (localized mode only).
void label_from_top_sites(const Mesh& m, HeatVoronoi& V) {
  const int32_t n = m.num_vertices();
  if (V.top_site.empty()) return;  // keep_hottest_only: the labels are the lists (every vertex had one)
  V.label.assign(n, -1);
  for (int32_t v = 0; v < n; ++v) V.label[v] = V.top_site[static_cast<size_t>(v) * V.top_k];
  const bool all_reached = std::find(V.label.begin(), V.label.end(), -1) == V.label.end();
  if (all_reached) return;
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

// The generators order[8b .. 8b+7] of every batch b solved and merged into V's
// top-K lists (V sized for the mesh). neighborhoods (indexed by generator id minus
// nb_first) or batch_kept (per batch) or neither (full solves).
void solve_into(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                std::span<const int32_t> order, std::span<const std::vector<int32_t>> neighborhoods, int32_t nb_first,
                const BatchKept& batch_kept, HeatVoronoi& V, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  const bool local = !neighborhoods.empty() || static_cast<bool>(batch_kept);
  const int32_t nb = static_cast<int32_t>((order.size() + kLanes - 1) / kLanes);
  V.batches += nb;
  tbb::enumerable_thread_specific<HeatBatch> scratch;

  auto solve_batch = [&](int32_t b) {
    HeatBatch& hb = scratch.local();
    auto msg = std::make_shared<VoronoiMsg>();
    hb.clear_sources();
    hb.kept.clear();
    const int32_t first = b * kLanes;
    msg->lanes = std::min<int32_t>(kLanes, static_cast<int32_t>(order.size()) - first);
    int32_t sites_of[kLanes];
    for (int l = 0; l < msg->lanes; ++l) {
      const int32_t s = order[first + l];
      sites_of[l] = s;
      int32_t v[3];
      double w[3];
      const int c = surface_point_support(m, sites[s], v, w);
      hb.add_source({v, static_cast<size_t>(c)}, {w, static_cast<size_t>(c)});
      if (!neighborhoods.empty()) {
        const std::vector<int32_t>& nbh = neighborhoods[s - nb_first];
        hb.kept.insert(hb.kept.end(), nbh.begin(), nbh.end());
      }
      if (local) hb.kept.insert(hb.kept.end(), v, v + c);
    }
    if (batch_kept) batch_kept(b, hb.kept);
    if (local) {
      dedupe_kept(hb, n);  // first occurrences, in order: no sort needed by the plan
    }
    const double c0 = thread_cpu_seconds();
    solve_heat_batch(H, hb);
    msg->solve_cpu_s = thread_cpu_seconds() - c0;
    msg->full = !local;
    if (local) msg->ids.assign(hb.kept.begin(), hb.kept.end());
    const int32_t cnt = hb.count();
    const int pv = std::min(msg->lanes, V.top_k);
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
    const size_t stride = static_cast<size_t>(V.top_k);
    for (int32_t k = 0; k < cnt; ++k) {
      const int32_t v = msg->full ? k : msg->ids[k];
      int32_t* ts = V.top_site.empty() ? V.label.data() + v : V.top_site.data() + static_cast<size_t>(v) * stride;
      double* tv = V.top_value.data() + static_cast<size_t>(v) * stride;
      for (int i = 0; i < pv; ++i) {
        const int32_t s = msg->cand_site[static_cast<size_t>(k) * pv + i];
        const double x = msg->cand_value[static_cast<size_t>(k) * pv + i];
        if (!(stride == 1 ? insert_top<1>(ts, tv, s, x) : insert_top(ts, tv, s, x)))
          break;  // the remaining candidates are colder
      }
    }
  };
  run_batch_graph<VoronoiMsg>(ctx, nb, solve_batch, reduce, "heat voronoi");
}

HeatVoronoi heat_voronoi_impl(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                              std::span<const std::vector<int32_t>> neighborhoods,
                              const BatchKept& batch_kept, std::span<const int32_t> batch_order,
                              const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  if (n != H.n) fail(ErrorCode::BadUsage, "heat voronoi: the operator was prepared for another mesh");
  if (sites.empty()) fail(ErrorCode::BadUsage, "heat voronoi: no generators");
  for (size_t i = 0; i < sites.size(); ++i) check_surface_point(m, sites[i], "generator", i);
  if (!neighborhoods.empty() && neighborhoods.size() != sites.size())
    fail(ErrorCode::BadUsage, "heat voronoi: one neighborhood per generator expected");
  const std::vector<int32_t> order = generator_order(sites.size(), batch_order);
  HeatVoronoi V;
  V.top_site.assign(static_cast<size_t>(n) * kVoronoiTopK, -1);
  V.top_value.assign(static_cast<size_t>(n) * kVoronoiTopK, 0.0);
  solve_into(H, m, sites, order, neighborhoods, 0, batch_kept, V, ctx);
  label_from_top_sites(m, V);
  return V;
}

}  // namespace

void heat_voronoi_add(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites, int32_t first_new,
                      std::span<const std::vector<int32_t>> new_neighborhoods, std::span<const int32_t> new_order,
                      HeatVoronoi& V, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(sites.size());
  if (n != H.n) fail(ErrorCode::BadUsage, "heat voronoi: the operator was prepared for another mesh");
  const bool sites_are_labels = V.top_k == 1 && V.top_site.empty();  // keep_hottest_only
  if ((V.top_k != 1 && V.top_k != kVoronoiTopK) || !V.top_offsets.empty() ||
      (!sites_are_labels && V.top_site.size() != static_cast<size_t>(n) * V.top_k) ||
      V.top_value.size() != static_cast<size_t>(n) * V.top_k || V.label.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "heat voronoi: the diagram to add to belongs to another mesh");
  if (first_new < 1 || first_new > ns) fail(ErrorCode::BadUsage, "heat voronoi: the old generators must come first");
  if (new_neighborhoods.size() != static_cast<size_t>(ns - first_new))
    fail(ErrorCode::BadUsage, "heat voronoi: one neighborhood per new generator expected");
  for (int32_t i = first_new; i < ns; ++i) check_surface_point(m, sites[i], "generator", i);
  std::vector<int32_t> order(new_order.begin(), new_order.end());
  if (order.empty())
    for (int32_t s = first_new; s < ns; ++s) order.push_back(s);
  std::vector<int32_t> check = order;
  std::sort(check.begin(), check.end());
  bool permutation = check.size() == static_cast<size_t>(ns - first_new);
  for (size_t i = 0; permutation && i < check.size(); ++i) permutation = check[i] == first_new + static_cast<int32_t>(i);
  if (!permutation) fail(ErrorCode::BadUsage, "heat voronoi: the order of the new generators is not a permutation of them");
  if (order.empty()) return;
  solve_into(H, m, sites, order, new_neighborhoods, first_new, {}, V, ctx);
  const int64_t unreached = V.unreached;
  label_from_top_sites(m, V);  // every vertex had a label: no fallback
  V.unreached = unreached;
  // The solves' workspaces (a few MB per thread at 416k vertices), freed: not
  // resident through a CVT repair's next steps (its peak, beside the factor).
  release_free_memory();
}

void keep_hottest_only(HeatVoronoi& V) {
  if (V.top_k == 1) return;
  const size_t n = V.label.size(), k = static_cast<size_t>(V.top_k);
  if (V.top_site.size() != n * k || V.top_value.size() != n * k || !V.top_offsets.empty())
    fail(ErrorCode::BadUsage, "heat voronoi: top-K lists and labels do not match");
  // The hottest sites are the labels unless the breadth-first fallback labelled
  // a vertex no site reached (its list stays empty: kept apart then).
  bool same = true;
  for (size_t v = 0; v < n && same; ++v) same = V.top_site[v * k] == V.label[v];
  HostVector<int32_t> ts(same ? 0 : n);
  HostVector<double> tv(n);
  for (size_t v = 0; v < n; ++v) {
    if (!same) ts[v] = V.top_site[v * k];
    tv[v] = V.top_value[v * k];
  }
  V.top_site = std::move(ts);
  V.top_value = std::move(tv);
  V.top_k = 1;
}

void keep_split_rows(HeatVoronoi& V, const Mesh& m) {
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  const size_t k = static_cast<size_t>(V.top_k);
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": split triangles need a triangle mesh");
  if (!V.top_offsets.empty() || V.top_k != kVoronoiTopK || V.label.size() != static_cast<size_t>(n) ||
      V.top_site.size() != n * k || V.top_value.size() != n * k)
    fail(ErrorCode::BadUsage, "heat voronoi: top-K lists and labels do not match");
  // Bit i of wanted[v]: entry i of v's list is the heat of a label of a split
  // triangle at v (the only heat the split reads there).
  static_assert(kVoronoiTopK <= 8, "one bit per entry");
  HostVector<uint8_t> wanted(static_cast<size_t>(n), 0);
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const int32_t l[3] = {V.label[v[0]], V.label[v[1]], V.label[v[2]]};
    if (l[0] == l[1] && l[1] == l[2]) continue;
    for (int32_t w : v)
      for (size_t i = 0; i < k; ++i) {
        const int32_t s = V.top_site[w * k + i];
        if (s >= 0 && (s == l[0] || s == l[1] || s == l[2])) wanted[w] |= static_cast<uint8_t>(1u << i);
      }
  }
  HostVector<int32_t> offsets(static_cast<size_t>(n) + 1);
  size_t kept = 0;
  for (int32_t v = 0; v < n; ++v) {
    offsets[v] = static_cast<int32_t>(kept);
    for (size_t i = 0; i < k; ++i)
      if (wanted[v] >> i & 1) {  // forward, in place: entry `kept` lies at or before entry v k + i
        V.top_site[kept] = V.top_site[v * k + i];
        V.top_value[kept] = V.top_value[v * k + i];
        ++kept;
      }
  }
  offsets[n] = static_cast<int32_t>(kept);
  // Copied to arrays of their size (one at a time: the transient is the smaller one).
  V.top_site = HostVector<int32_t>(V.top_site.begin(), V.top_site.begin() + static_cast<std::ptrdiff_t>(kept));
  V.top_value = HostVector<double>(V.top_value.begin(), V.top_value.begin() + static_cast<std::ptrdiff_t>(kept));
  V.top_offsets = std::move(offsets);
}

HeatVoronoi heat_voronoi(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                         std::span<const std::vector<int32_t>> neighborhoods, std::span<const int32_t> batch_order,
                         const RunContext& ctx) {
  return heat_voronoi_impl(H, m, sites, neighborhoods, {}, batch_order, ctx);
}

HeatVoronoi heat_voronoi_batched(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                 std::span<const int32_t> batch_order,
                                 std::span<const HostVector<int32_t>> batch_kept, const RunContext& ctx) {
  if (batch_kept.empty()) fail(ErrorCode::BadUsage, "heat voronoi: no kept sets given");
  if (batch_kept.size() != (sites.size() + kLanes - 1) / kLanes)
    fail(ErrorCode::BadUsage, "heat voronoi: one kept set per batch of 8 generators expected");
  return heat_voronoi_impl(
      H, m, sites, {},
      [&](int32_t b, HostVector<int32_t>& kept) { kept.insert(kept.end(), batch_kept[b].begin(), batch_kept[b].end()); },
      batch_order, ctx);
}

HeatVoronoi heat_voronoi_batched(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                 std::span<const int32_t> batch_order, const BatchKept& batch_kept,
                                 const RunContext& ctx) {
  if (!batch_kept) fail(ErrorCode::BadUsage, "heat voronoi: no kept sets given");
  return heat_voronoi_impl(H, m, sites, {}, batch_kept, batch_order, ctx);
}

namespace {

struct MissingValue {
  int32_t site, vertex;
  double value;
};

// (site, vertex) ascending: the order of the solved missing values.
bool site_vertex_less(const MissingValue& a, const MissingValue& b) {
  return a.site != b.site ? a.site < b.site : a.vertex < b.vertex;
}

// Heat of site s at vertex v: from v's top-K list, else from the values solved
// because no top-K list held them (sorted by site_vertex_less).
class HeatLookup {
 public:
  explicit HeatLookup(const HeatVoronoi& V) : V_(V) {}
  double operator()(int32_t v, int32_t s, bool& found) const {
    const int32_t* ts = V_.top_site.data() + static_cast<size_t>(v) * kVoronoiTopK;
    for (int i = 0; i < kVoronoiTopK; ++i)
      if (ts[i] == s) {
        found = true;
        return V_.top_value[static_cast<size_t>(v) * kVoronoiTopK + i];
      }
    auto it = std::lower_bound(missing_.begin(), missing_.end(), MissingValue{s, v, 0}, site_vertex_less);
    if (it != missing_.end() && it->site == s && it->vertex == v) {
      found = true;
      return it->value;
    }
    found = false;
    return 0.0;
  }
  double operator()(int32_t v, int32_t s) const {
    bool found = false;
    return (*this)(v, s, found);
  }
  void set_missing(std::vector<MissingValue>& solved) { missing_.swap(solved); }

 private:
  const HeatVoronoi& V_;
  std::vector<MissingValue> missing_;
};

// Pass 1: the heat values of neighboring labels (across a triangle) that no top-K
// list holds, unique and sorted by site_vertex_less.
std::vector<MissingValue> find_missing_values(const Mesh& m, const HeatVoronoi& V, const HeatLookup& lookup) {
  std::vector<MissingValue> need;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        if (a == b || V.label[v[a]] == V.label[v[b]]) continue;
        bool found = false;
        lookup(v[a], V.label[v[b]], found);
        if (!found) need.push_back({V.label[v[b]], v[a], 0});
      }
  }
  if (need.empty()) return need;
  std::sort(need.begin(), need.end(), site_vertex_less);
  need.erase(std::unique(need.begin(), need.end(),
                         [](const MissingValue& a, const MissingValue& b) {
                           return a.site == b.site && a.vertex == b.vertex;
                         }),
             need.end());
  return need;
}

// Fills need[].value by full solves of the sites involved, 8 sites per solve.
void solve_missing_values(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                          std::vector<MissingValue>& need, const RunContext& ctx) {
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
}

// Segments of the diagram, triangle by triangle (eqs. 3.19-3.21): points on the
// edges whose ends carry two labels (shared by the edge's two triangles) and one
// corner point per triangle with three labels.
class DiagramSegments {
 public:
  DiagramSegments(const Mesh& m, const HeatVoronoi& V, const HeatLookup& u, VoronoiDiagram& D)
      : m_(m), V_(V), u_(u), D_(D), inc_(edge_incidence(m)), edge_point_(inc_.edges.e0.size(), -1) {}

  void add_face(int32_t f) {
    const Mesh& m = m_;
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const int32_t l[3] = {V_.label[v[0]], V_.label[v[1]], V_.label[v[2]]};
    if (l[0] == l[1] && l[1] == l[2]) return;
    // Corner c's half-edge runs v[c] -> v[c+1].
    if (l[0] != l[1] && l[1] != l[2] && l[0] != l[2]) {
      add_corner(f, v, l);
      return;
    }
    // Two labels: the odd vertex k; the segment joins the points on its two edges.
    const int k = l[0] == l[1] ? 2 : (l[1] == l[2] ? 0 : 1);
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    // Edge (k, i) is corner k's half-edge, edge (j, k) is corner j's.
    const int32_t pa = edge_pt(f, k, v[k], v[i]);
    const int32_t pb = edge_pt(f, j, v[j], v[k]);
    D_.segments.insert(D_.segments.end(), {pa, pb});
  }

 private:
  int32_t add_point(double x, double y, double z, int32_t sa, int32_t sb) {
    D_.points.insert(D_.points.end(), {x, y, z});
    D_.point_edge_sites.insert(D_.point_edge_sites.end(), {sa, sb});
    return static_cast<int32_t>(D_.points.size() / 3 - 1);
  }
  // Point on edge (i, k) where the interpolants of l_i and l_k are equal (eqs. 3.19, 3.20).
  int32_t edge_pt(int32_t f, int corner_i, int32_t i, int32_t k) {
    const Mesh& m = m_;
    const HeatLookup& u = u_;
    const int32_t e = inc_.corner_edge[m.face_offsets[f] + corner_i];
    if (edge_point_[e] >= 0) return edge_point_[e];
    const int32_t a = V_.label[i], b = V_.label[k];
    const double den = u(i, a) - u(k, a) - u(i, b) + u(k, b);
    double beta = den > 0 ? (u(k, b) - u(k, a)) / den : 0.5;
    beta = std::clamp(beta, 0.0, 1.0);
    edge_point_[e] = add_point(beta * m.x[i] + (1 - beta) * m.x[k], beta * m.y[i] + (1 - beta) * m.y[k],
                               beta * m.z[i] + (1 - beta) * m.z[k], std::min(a, b), std::max(a, b));
    return edge_point_[e];
  }
  // Three labels: a Voronoi corner (eq. 3.21) joined to the three edge points.
  void add_corner(int32_t f, const int32_t v[3], const int32_t l[3]) {
    const Mesh& m = m_;
    const HeatLookup& u = u_;
    const int32_t p01 = edge_pt(f, 0, v[0], v[1]), p12 = edge_pt(f, 1, v[1], v[2]), p20 = edge_pt(f, 2, v[2], v[0]);
    const double w0 = u(v[0], l[0]), w1 = u(v[1], l[1]), w2 = u(v[2], l[2]);
    const double ws = w0 + w1 + w2;
    const double c0 = ws > 0 ? w0 / ws : 1.0 / 3, c1 = ws > 0 ? w1 / ws : 1.0 / 3, c2 = ws > 0 ? w2 / ws : 1.0 / 3;
    const int32_t pc = add_point(c0 * m.x[v[0]] + c1 * m.x[v[1]] + c2 * m.x[v[2]],
                                 c0 * m.y[v[0]] + c1 * m.y[v[1]] + c2 * m.y[v[2]],
                                 c0 * m.z[v[0]] + c1 * m.z[v[1]] + c2 * m.z[v[2]], -1, -1);  // eq. 3.21
    ++D_.corners;
    D_.segments.insert(D_.segments.end(), {pc, p01, pc, p12, pc, p20});
  }

  const Mesh& m_;
  const HeatVoronoi& V_;
  const HeatLookup& u_;
  VoronoiDiagram& D_;
  const EdgeIncidence inc_;
  std::vector<int32_t> edge_point_;
};

// Chains D's segments into polylines through points of degree 2: first the open
// chains (from points of another degree), then the closed loops.
void chain_polylines(VoronoiDiagram& D) {
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
}

}  // namespace

VoronoiDiagram extract_voronoi_diagram(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                       const HeatVoronoi& V, const RunContext& ctx) {
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  if (static_cast<int32_t>(V.label.size()) != n || n != H.n)
    fail(ErrorCode::BadUsage, "voronoi diagram: labels were computed for another mesh");
  if (V.top_k != kVoronoiTopK || V.top_site.size() != static_cast<size_t>(n) * kVoronoiTopK || !V.top_offsets.empty())
    fail(ErrorCode::BadUsage, "voronoi diagram: the neighbors' heat needs the full top-K lists");
  VoronoiDiagram D;
  HeatLookup lookup(V);
  std::vector<MissingValue> need = find_missing_values(m, V, lookup);
  if (!need.empty()) {
    solve_missing_values(H, m, sites, need, ctx);
    D.resolved_missing = static_cast<int64_t>(need.size());
    lookup.set_missing(need);
  }
  DiagramSegments segments(m, V, lookup, D);
  for (int32_t f = 0; f < nf; ++f) segments.add_face(f);
  chain_polylines(D);
  return D;
}

}  // namespace locus
