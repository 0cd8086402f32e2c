// Natural-neighbor (area-stealing) coordinates with heat-diffusion cells
// (pipelines/include/locus/pipelines/voronoi/natural_neighbor.hpp; thesis §3.7.2).
#include "locus/pipelines/voronoi/natural_neighbor.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/voronoi_cell_partition.hpp"

namespace locus {

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
  F.cell_area = std::vector<double>(partition_cells(m, F.face_area, F.voronoi, static_cast<int32_t>(sites.size())).area);
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

NaturalCoordinates natural_neighbor_coordinates(const NaturalNeighborField& F, const Mesh& m,
                                                 const SurfacePoint& q, std::span<const double> heat_q) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(F.sites.size());
  if (!F.heat || F.heat->n != n || F.voronoi.label.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "natural neighbors: the field was prepared for another mesh");
  if (heat_q.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "natural neighbors: the query's heat needs one value per vertex");
  check_surface_point(m, q, "query point", 0);
  NaturalCoordinates r;
  r.weight.assign(ns, 0.0);
  const auto pq = surface_point_position(m, q);
  const double tol = 1e-9 * F.heat->h;
  for (int32_t s = 0; s < ns; ++s) {
    const auto& p = F.site_position[s];
    const double d = std::sqrt((p[0] - pq[0]) * (p[0] - pq[0]) + (p[1] - pq[1]) * (p[1] - pq[1]) +
                               (p[2] - pq[2]) * (p[2] - pq[2]));
    if (d <= tol) {
      r.weight[s] = 1.0;
      r.at_site = true;
      return r;
    }
  }
  const HeatVoronoi& V = F.voronoi;
  // Vertices q takes over: its heat beats the current maximum (ties stay with the sites).
  std::vector<int32_t> taken;
  for (int32_t v = 0; v < n; ++v) {
    if (!std::isfinite(heat_q[v])) fail(ErrorCode::Numerical, "natural neighbors: the query's heat is not finite");
    if (heat_q[v] > V.top_value[static_cast<size_t>(v) * kVoronoiTopK]) taken.push_back(v);
  }
  auto site_heat = [&](int32_t v, int32_t s, bool& ok) { return top_heat(V, v, s, ok); };
  if (taken.empty()) {  // q's cell holds no vertex: the cell containing q
    r.weight[containing_cell(V, m, q)] = 1.0;
    r.degenerate = true;
    return r;
  }
  std::vector<int32_t> faces;
  for (int32_t v : taken) faces.insert(faces.end(), F.vf_faces.begin() + F.vf_offsets[v], F.vf_faces.begin() + F.vf_offsets[v + 1]);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  auto is_taken = [&](int32_t v) { return std::binary_search(taken.begin(), taken.end(), v); };
  std::vector<double> stolen(ns, 0.0);
  double aq = 0;
  for (int32_t f : faces) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const double A = F.face_area[f];
    const int32_t lold[3] = {V.label[v[0]], V.label[v[1]], V.label[v[2]]};
    int32_t lnew[3];
    for (int k = 0; k < 3; ++k) lnew[k] = is_taken(v[k]) ? ns : lold[k];
    bool ok_old = true, ok_new = true;
    ok_old = split_face(
        A, lold, [&](int k, int32_t s, bool& ok) { return site_heat(v[k], s, ok); },
        [&](int32_t s, double a) { stolen[s] += a; });
    ok_new = split_face(
        A, lnew,
        [&](int k, int32_t s, bool& ok) { return s == ns ? heat_q[v[k]] : site_heat(v[k], s, ok); },
        [&](int32_t s, double a) {
          if (s == ns) {
            aq += a;
          } else {
            stolen[s] -= a;
          }
        });
    r.fallback_faces += !ok_old || !ok_new;
  }
  r.cell_area = aq;
  if (!(aq > 0)) fail(ErrorCode::Numerical, "natural neighbors: the query's cell has no area");
  double sum = 0, neg = 0;
  for (int32_t s = 0; s < ns; ++s) {
    if (stolen[s] < 0) {
      neg -= stolen[s];
      stolen[s] = 0;
    }
    sum += stolen[s];
  }
  r.clamped = neg / aq;
  if (!(sum > 0)) fail(ErrorCode::Numerical, "natural neighbors: no area was stolen");
  for (int32_t s = 0; s < ns; ++s) r.weight[s] = stolen[s] / sum;
  return r;
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
