// Natural-neighbor (area-stealing) coordinates with heat-diffusion cells
// (pipelines/include/locus/pipelines/voronoi/natural_neighbor.hpp; thesis §3.7.2).
#include "locus/pipelines/voronoi/natural_neighbor.hpp"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <string>

#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/mesh/lifted_metric.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/voronoi_cell_partition.hpp"

namespace locus {

namespace {

void finish_field(NaturalNeighborField& F, const Mesh& m, int32_t ns);

// (heat desc, site asc), the total order of heat_voronoi.hpp's top-K lists.
void insert_top(int32_t* ts, double* tv, int32_t s, double v) {
  auto hotter = [](double a, int32_t sa, double b, int32_t sb) { return sb < 0 || a > b || (a == b && sa < sb); };
  if (!hotter(v, s, tv[kVoronoiTopK - 1], ts[kVoronoiTopK - 1])) return;
  int i = kVoronoiTopK - 1;
  for (; i > 0 && hotter(v, s, tv[i - 1], ts[i - 1]); --i) {
    ts[i] = ts[i - 1];
    tv[i] = tv[i - 1];
  }
  ts[i] = s;
  tv[i] = v;
}

// Heat Voronoi of vertex-set sites (a unit source at every vertex of a set): full
// solves, 8 sets at a time; the top-K lists and labels of heat_voronoi.hpp.
HeatVoronoi set_voronoi(const HeatDiffusion& H, const Mesh& m, std::span<const std::vector<int32_t>> sets,
                        const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(sets.size());
  HeatVoronoi V;
  V.top_site.assign(static_cast<size_t>(n) * kVoronoiTopK, -1);
  V.top_value.assign(static_cast<size_t>(n) * kVoronoiTopK, 0.0);
  HeatBatch hb;
  std::vector<double> ones;
  for (int32_t first = 0; first < ns; first += kLanes) {
    ctx.check_cancel();
    const int lanes = std::min<int32_t>(kLanes, ns - first);
    hb.clear_sources();
    hb.kept.clear();
    for (int l = 0; l < lanes; ++l) {
      ones.assign(sets[first + l].size(), 1.0);
      hb.add_source(sets[first + l], ones);
    }
    solve_heat_batch(H, hb);
    ++V.batches;
    V.solved_entries += n;
    for (int32_t v = 0; v < n; ++v)
      for (int l = 0; l < lanes; ++l)
        insert_top(V.top_site.data() + static_cast<size_t>(v) * kVoronoiTopK,
                   V.top_value.data() + static_cast<size_t>(v) * kVoronoiTopK, first + l,
                   hb.values[static_cast<size_t>(v) * kLanes + l]);
  }
  V.label.resize(n);
  for (int32_t v = 0; v < n; ++v) V.label[v] = V.top_site[static_cast<size_t>(v) * kVoronoiTopK];
  return V;
}

}  // namespace

NaturalNeighborField prepare_natural_neighbors(const HeatDiffusion& H, const Mesh& m,
                                                 std::span<const SurfacePoint> sites, const RunContext& ctx) {
  if (H.n != m.num_vertices()) fail(ErrorCode::BadUsage, "natural neighbors: the operator belongs to another mesh");
  if (sites.empty()) fail(ErrorCode::BadUsage, "natural neighbors: no sites");
  NaturalNeighborField F;
  F.heat = &H;
  F.sites.assign(sites.begin(), sites.end());
  for (size_t i = 0; i < sites.size(); ++i) {
    check_surface_point(m, sites[i], "site", i);
    F.site_position.push_back(surface_point_position(m, sites[i]));
  }
  F.voronoi = heat_voronoi(H, m, sites, {}, {}, ctx);
  finish_field(F, m, static_cast<int32_t>(sites.size()));
  return F;
}

NaturalNeighborField prepare_natural_neighbors(const HeatDiffusion& H, const Mesh& m,
                                                 std::span<const std::vector<int32_t>> sets, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  if (H.n != n) fail(ErrorCode::BadUsage, "natural neighbors: the operator belongs to another mesh");
  if (sets.empty()) fail(ErrorCode::BadUsage, "natural neighbors: no sites");
  std::vector<int32_t> owner(n, -1);
  for (size_t i = 0; i < sets.size(); ++i) {
    if (sets[i].empty()) fail(ErrorCode::BadUsage, "natural neighbors: site " + std::to_string(i) + " has no vertex");
    for (int32_t v : sets[i]) {
      if (v < 0 || v >= n)
        fail(ErrorCode::BadUsage, "natural neighbors: site " + std::to_string(i) + " names vertex " +
                                      std::to_string(v) + " but the mesh has " + std::to_string(n) + " vertices");
      if (owner[v] >= 0 && owner[v] != static_cast<int32_t>(i))
        fail(ErrorCode::BadUsage, "natural neighbors: vertex " + std::to_string(v) + " is in sites " +
                                      std::to_string(owner[v]) + " and " + std::to_string(i));
      owner[v] = static_cast<int32_t>(i);
    }
  }
  NaturalNeighborField F;
  F.heat = &H;
  for (const auto& set : sets) {
    F.sites.push_back(vertex_point(set.front()));
    F.site_position.push_back(surface_point_position(m, F.sites.back()));
  }
  F.voronoi = set_voronoi(H, m, sets, ctx);
  finish_field(F, m, static_cast<int32_t>(sets.size()));
  return F;
}

namespace {

// Areas of the parts of face f for corner labels l[3]; heat(k, label, ok) gives the
// heat of `label` at corner k. Adds A * fraction to area[label] via `add`.
template <class Heat, class Add>
bool split_face(double A, const int32_t l[3], Heat&& heat, Add&& add) {
  int32_t lab[3];
  int nl = 0;
  for (int k = 0; k < 3; ++k)
    if (std::find(lab, lab + nl, l[k]) == lab + nl) lab[nl++] = l[k];
  if (nl == 1) {
    add(lab[0], A);
    return true;
  }
  double u[3][3];
  bool ok = true;
  for (int a = 0; a < nl; ++a)
    for (int k = 0; k < 3; ++k) u[a][k] = heat(k, lab[a], ok);
  if (!ok) {  // by vertex labels: a third of the area per corner
    for (int k = 0; k < 3; ++k) add(l[k], A / 3);
    return false;
  }
  double frac[3], cen[3][3];
  split_triangle(nl, lab, u, frac, cen);
  for (int a = 0; a < nl; ++a) add(lab[a], A * frac[a]);
  return true;
}

// Heat of site s at vertex v from v's top-K list; ok = false when the list lacks s.
double top_heat(const HeatVoronoi& V, int32_t v, int32_t s, bool& ok) {
  const size_t base = static_cast<size_t>(v) * kVoronoiTopK;
  for (int i = 0; i < kVoronoiTopK; ++i)
    if (V.top_site[base + i] == s) return V.top_value[base + i];
  ok = false;
  return 0.0;
}

void finish_field(NaturalNeighborField& F, const Mesh& m, int32_t ns) {
  F.face_area = face_areas(m);
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  F.vf_offsets.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t f = 0; f < nf; ++f)
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) ++F.vf_offsets[v + 1];
  for (int32_t v = 0; v < n; ++v) F.vf_offsets[v + 1] += F.vf_offsets[v];
  F.vf_faces.resize(F.vf_offsets[n]);
  std::vector<int64_t> fill(F.vf_offsets.begin(), F.vf_offsets.end() - 1);
  for (int32_t f = 0; f < nf; ++f)
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) F.vf_faces[fill[v]++] = f;
  F.cell_area = std::vector<double>(partition_cells(m, F.face_area, F.voronoi, ns).area);
  // The split of every face before insertion, in the order a query adds it.
  F.part_site.assign(3 * static_cast<size_t>(nf), -1);
  F.part_area.assign(3 * static_cast<size_t>(nf), 0.0);
  F.part_fallback.assign(nf, 0);
  const HeatVoronoi& V = F.voronoi;
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const int32_t l[3] = {V.label[v[0]], V.label[v[1]], V.label[v[2]]};
    int used = 0;
    F.part_fallback[f] = !split_face(
        F.face_area[f], l, [&](int k, int32_t s, bool& ok) { return top_heat(V, v[k], s, ok); },
        [&](int32_t s, double a) {
          F.part_site[3 * static_cast<size_t>(f) + used] = s;
          F.part_area[3 * static_cast<size_t>(f) + used] = a;
          ++used;
        });
  }
  F.max_heat.resize(n);
  for (int32_t v = 0; v < n; ++v) F.max_heat[v] = V.top_value[static_cast<size_t>(v) * kVoronoiTopK];
  F.share_offsets.assign(static_cast<size_t>(n) + 1, 0);
  F.share_site.clear();
  F.share_area.clear();
  F.vertex_area.assign(n, 0.0);
  std::vector<double> acc(ns, 0.0);
  std::vector<int32_t> seen;
  for (int32_t v = 0; v < n; ++v) {
    for (int64_t p = F.vf_offsets[v]; p < F.vf_offsets[v + 1]; ++p) {
      const int32_t f = F.vf_faces[p];
      F.vertex_area[v] += F.face_area[f] / 3;
      for (int q = 0; q < 3; ++q) {
        const int32_t site = F.part_site[3 * static_cast<size_t>(f) + q];
        if (site < 0) continue;
        if (acc[site] == 0.0) seen.push_back(site);
        acc[site] += F.part_area[3 * static_cast<size_t>(f) + q] / 3;
      }
    }
    std::sort(seen.begin(), seen.end());
    for (int32_t site : seen) {
      F.share_site.push_back(site);
      F.share_area.push_back(acc[site]);
      acc[site] = 0.0;
    }
    seen.clear();
    F.share_offsets[v + 1] = static_cast<int64_t>(F.share_site.size());
  }
}

// The site whose cell contains q: among the labels of q's support vertices, the one
// whose heat interpolated at q is largest (smallest id on ties).
int32_t containing_cell(const HeatVoronoi& V, const Mesh& m, const SurfacePoint& q) {
  int32_t sv[3];
  double sw[3];
  const int c = surface_point_support(m, q, sv, sw);
  int32_t best = V.label[sv[0]];
  double bv = -INFINITY;
  for (int a = 0; a < c; ++a) {
    const int32_t s = V.label[sv[a]];
    double val = 0;
    bool ok = true;
    for (int k = 0; k < c; ++k) val += sw[k] * top_heat(V, sv[k], s, ok);
    if (ok && (val > bv || (val == bv && s < best))) {
      bv = val;
      best = s;
    }
  }
  return best;
}

}  // namespace

namespace {

// Queries of one batch: lane l's heat at vertex v is heat[v * stride + l].
struct LaneHeat {
  const double* heat;
  int stride;
  double operator()(int32_t v, int l) const { return heat[static_cast<size_t>(v) * stride + l]; }
  void prefetch(int32_t v) const { __builtin_prefetch(heat + static_cast<size_t>(v) * stride); }
};

constexpr size_t kFaceAhead = 8, kCornerAhead = 3;

// The vertices each lane takes (its heat beats the current maximum; ties stay with
// the sites) as bit l of s.vertex_mark (every vertex written), and in the same pass
// over the vertices the taken vertices' areas and shares into aq[l] and
// stolen[l * ns ..]: a third of each incident face per taken corner. Every lane
// sums in the order of its ascending taken vertices; a vertex's shares are read
// once for all the lanes that take it. Returns the lanes whose heat is not finite
// somewhere (8 lanes per vertex: compared without branches).
uint8_t take_vertices(const NaturalNeighborField& F, const LaneHeat& heat, uint8_t active, NaturalScratch& s,
                      std::vector<double>& stolen, double* aq, int64_t* count) {
  const int32_t n = static_cast<int32_t>(F.max_heat.size());
  const int32_t ns = static_cast<int32_t>(F.sites.size());
  uint8_t bad = 0;
  const bool wide = heat.stride == kLanes;  // 8 values per vertex: compared without branches
  for (int32_t v = 0; v < n; ++v) {
    uint8_t mask = 0;
    if (wide) {
      const double* h = heat.heat + static_cast<size_t>(v) * kLanes;
      const double mx = F.max_heat[v];
      uint32_t over = 0, nonfinite = 0;
      for (int l = 0; l < kLanes; ++l) {
        over |= static_cast<uint32_t>(h[l] > mx) << l;
        nonfinite |= static_cast<uint32_t>(!(std::abs(h[l]) <= DBL_MAX)) << l;
      }
      mask = static_cast<uint8_t>(over & active);
      bad |= static_cast<uint8_t>(nonfinite & active);
    } else {
      for (int l = 0; l < kLanes; ++l) {
        if (!(active >> l & 1)) continue;
        const double h = heat(v, l);
        if (!std::isfinite(h)) bad |= static_cast<uint8_t>(1u << l);
        if (h > F.max_heat[v]) mask |= static_cast<uint8_t>(1u << l);
      }
    }
    s.vertex_mark[v] = mask;
    if (!mask) continue;
    for (int l = 0; l < kLanes; ++l) {
      if (!(mask >> l & 1)) continue;
      ++count[l];
      double* st = stolen.data() + static_cast<size_t>(l) * ns;
      for (int64_t p = F.share_offsets[v]; p < F.share_offsets[v + 1]; ++p) st[F.share_site[p]] += F.share_area[p];
      aq[l] += F.vertex_area[v];
    }
  }
  return bad;
}

// The border faces of every lane (taken and untaken corners) into s.lane_faces[l],
// each in the order of its smallest taken corner, then by face id (the order in
// which a pass over the ascending taken vertices and their ascending faces meets
// them). One pass over the faces finds them for all lanes at once: a face is on
// lane l's border when bit l differs among its corners' marks (the marks are
// one byte per vertex: cache-resident); only border faces are then sorted.
void border_faces(const Mesh& m, NaturalScratch& s) {
  for (auto& keys : s.lane_keys) keys.clear();
  const int32_t nf = m.num_faces();
  const uint8_t* mark = s.vertex_mark.data();
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t c[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const uint8_t a = mark[c[0]], b = mark[c[1]], d = mark[c[2]];
    uint8_t border = static_cast<uint8_t>((a | b | d) & ~(a & b & d));
    while (border) {
      const int l = std::countr_zero(border);
      border &= static_cast<uint8_t>(border - 1);
      int32_t first = INT32_MAX;
      for (int32_t u : c)
        if (mark[u] >> l & 1) first = std::min(first, u);
      s.lane_keys[l].push_back(static_cast<int64_t>(first) << 32 | f);
    }
  }
  for (int l = 0; l < kLanes; ++l) {
    std::sort(s.lane_keys[l].begin(), s.lane_keys[l].end());
    s.lane_faces[l].clear();
    for (int64_t key : s.lane_keys[l]) s.lane_faces[l].push_back(static_cast<int32_t>(key & 0xffffffff));
  }
}

// Lane l's border faces: the rest of their old parts (the untaken corners' thirds)
// is stolen too, the taken corners' thirds leave aq, and their re-split with q
// as an extra site is taken back. Returns the faces split by vertex labels.
int64_t resplit_border(const NaturalNeighborField& F, const Mesh& m, const LaneHeat& heat, int l,
                       const NaturalScratch& s, double* stolen, double& aq) {
  const HeatVoronoi& V = F.voronoi;
  const int32_t ns = static_cast<int32_t>(F.sites.size());
  int64_t fallback = 0;
  const std::vector<int32_t>& faces = s.lane_faces[l];
  const size_t nb = faces.size();
  for (size_t i = 0; i < nb; ++i) {
    // The faces are scattered: their records are fetched a few faces ahead, their
    // corners' top-K lists and heat rows two ahead (latency, not work, is the cost).
    if (i + kFaceAhead < nb) {
      const int32_t g = faces[i + kFaceAhead];
      __builtin_prefetch(&m.f0[g]);
      __builtin_prefetch(&m.f1[g]);
      __builtin_prefetch(&m.f2[g]);
      __builtin_prefetch(&F.part_site[3 * static_cast<size_t>(g)]);
      __builtin_prefetch(&F.part_area[3 * static_cast<size_t>(g)]);
      __builtin_prefetch(&F.face_area[g]);
    }
    if (i + kCornerAhead < nb) {
      const int32_t g = faces[i + kCornerAhead];
      for (int32_t u : {m.f0[g], m.f1[g], m.f2[g]}) {
        __builtin_prefetch(&V.top_site[static_cast<size_t>(u) * kVoronoiTopK]);
        __builtin_prefetch(&V.top_value[static_cast<size_t>(u) * kVoronoiTopK]);
        __builtin_prefetch(&V.label[u]);
        heat.prefetch(u);
      }
    }
    const int32_t f = faces[i];
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const bool t[3] = {(s.vertex_mark[v[0]] >> l & 1) != 0, (s.vertex_mark[v[1]] >> l & 1) != 0,
                       (s.vertex_mark[v[2]] >> l & 1) != 0};
    const int taken = t[0] + t[1] + t[2];
    const double rest = (3 - taken) / 3.0;
    for (int p = 0; p < 3; ++p) {
      const int32_t site = F.part_site[3 * static_cast<size_t>(f) + p];
      if (site >= 0) stolen[site] += rest * F.part_area[3 * static_cast<size_t>(f) + p];
    }
    aq -= taken * F.face_area[f] / 3;  // the taken corners' thirds: replaced by the new split
    const int32_t lnew[3] = {t[0] ? ns : V.label[v[0]], t[1] ? ns : V.label[v[1]], t[2] ? ns : V.label[v[2]]};
    const bool ok = split_face(
        F.face_area[f], lnew,
        [&](int k, int32_t site, bool& okk) { return site == ns ? heat(v[k], l) : top_heat(V, v[k], site, okk); },
        [&](int32_t site, double a) {
          if (site == ns) {
            aq += a;
          } else {
            stolen[site] -= a;
          }
        });
    fallback += !ok || F.part_fallback[f];
  }
  return fallback;
}

// The coordinates from q's cell area aq and the areas it steals.
void finish_coordinates(double* stolen, int32_t ns, double aq, NaturalCoordinates& r) {
  r.cell_area = aq;
  if (!(aq > 0)) fail(ErrorCode::Numerical, "natural neighbors: the query's cell has no area");
  double sum = 0, neg = 0;
  // Areas summed in a different order than they were split leave rounding
  // residues (|x| ~ 1e-16 aq) where nothing was stolen: those are zero.
  const double tiny = 1e-12 * aq;
  for (int32_t i = 0; i < ns; ++i) {
    if (stolen[i] < 0) neg -= stolen[i];
    if (stolen[i] <= tiny) stolen[i] = 0;
    sum += stolen[i];
  }
  r.clamped = neg / aq;
  if (!(sum > 0)) fail(ErrorCode::Numerical, "natural neighbors: no area was stolen");
  for (int32_t i = 0; i < ns; ++i) r.weight[i] = stolen[i] / sum;
}

// Up to 8 queries on one pass over the vertices (the single query is lane 0).
void coordinates_lanes(const NaturalNeighborField& F, const Mesh& m, std::span<const SurfacePoint> q,
                       const LaneHeat& heat, NaturalScratch& s, NaturalCoordinates* out) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(F.sites.size());
  const int lanes = static_cast<int>(q.size());
  const double tol = 1e-9 * F.heat->h;
  uint8_t active = 0;
  for (int l = 0; l < lanes; ++l) {
    check_surface_point(m, q[l], "query point", l);
    NaturalCoordinates& r = out[l];
    r = NaturalCoordinates{};
    r.weight.assign(ns, 0.0);
    const auto pq = surface_point_position(m, q[l]);
    for (int32_t i = 0; i < ns && !r.at_site; ++i) {
      const auto& p = F.site_position[i];
      const double d = std::sqrt((p[0] - pq[0]) * (p[0] - pq[0]) + (p[1] - pq[1]) * (p[1] - pq[1]) +
                                 (p[2] - pq[2]) * (p[2] - pq[2]));
      if (d <= tol) {
        r.weight[i] = 1.0;
        r.at_site = true;
      }
    }
    if (r.at_site) continue;
    active |= static_cast<uint8_t>(1u << l);
  }
  if (!active) return;
  s.vertex_mark.resize(n, 0);
  std::vector<double> stolen(static_cast<size_t>(kLanes) * ns, 0.0);
  double aq[kLanes] = {};
  int64_t count[kLanes] = {};
  if (take_vertices(F, heat, active, s, stolen, aq, count))
    fail(ErrorCode::Numerical, "natural neighbors: the query's heat is not finite");
  border_faces(m, s);
  for (int l = 0; l < lanes; ++l) {
    if (!(active >> l & 1)) continue;
    NaturalCoordinates& r = out[l];
    if (count[l] == 0) {  // q's cell holds no vertex: the cell containing q
      r.weight[containing_cell(F.voronoi, m, q[l])] = 1.0;
      r.degenerate = true;
      continue;
    }
    double* st = stolen.data() + static_cast<size_t>(l) * ns;
    r.fallback_faces = resplit_border(F, m, heat, l, s, st, aq[l]);
    finish_coordinates(st, ns, aq[l], r);
  }
}

void check_field(const NaturalNeighborField& F, int32_t n) {
  if (!F.heat || F.heat->n != n || F.voronoi.label.size() != static_cast<size_t>(n) ||
      F.max_heat.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "natural neighbors: the field was prepared for another mesh");
}

}  // namespace

NaturalCoordinates natural_neighbor_coordinates(const NaturalNeighborField& F, const Mesh& m,
                                                 const SurfacePoint& q, std::span<const double> heat_q,
                                                 NaturalScratch& scratch) {
  check_field(F, m.num_vertices());
  if (heat_q.size() != static_cast<size_t>(m.num_vertices()))
    fail(ErrorCode::BadUsage, "natural neighbors: the query's heat needs one value per vertex");
  NaturalCoordinates r;
  coordinates_lanes(F, m, {&q, 1}, LaneHeat{heat_q.data(), 1}, scratch, &r);
  return r;
}

NaturalCoordinates natural_neighbor_coordinates(const NaturalNeighborField& F, const Mesh& m,
                                                 const SurfacePoint& q, std::span<const double> heat_q) {
  NaturalScratch scratch;
  return natural_neighbor_coordinates(F, m, q, heat_q, scratch);
}

void natural_neighbor_coordinates8(const NaturalNeighborField& F, const Mesh& m, std::span<const SurfacePoint> q,
                                   std::span<const double> heat8, NaturalScratch& scratch,
                                   std::span<NaturalCoordinates> out) {
  check_field(F, m.num_vertices());
  if (q.size() > static_cast<size_t>(kLanes) || out.size() < q.size())
    fail(ErrorCode::BadUsage, "natural neighbors: up to 8 queries per batch, one result each");
  if (heat8.size() != static_cast<size_t>(m.num_vertices()) * kLanes)
    fail(ErrorCode::BadUsage, "natural neighbors: the batch's heat needs 8 values per vertex");
  coordinates_lanes(F, m, q, LaneHeat{heat8.data(), kLanes}, scratch, out.data());
}

NaturalCoordinates natural_neighbor_coordinates(const NaturalNeighborField& F, const Mesh& m,
                                                 const SurfacePoint& q) {
  if (!F.heat) fail(ErrorCode::BadUsage, "natural neighbors: the field is not prepared");
  check_surface_point(m, q, "query point", 0);
  std::vector<double> u(m.num_vertices(), 0.0);
  int32_t sv[3];
  double sw[3];
  const int c = surface_point_support(m, q, sv, sw);
  for (int k = 0; k < c; ++k) u[sv[k]] += sw[k];
  solve(F.heat->factor, u);
  return natural_neighbor_coordinates(F, m, q, u);
}

}  // namespace locus
