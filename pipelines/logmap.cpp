// Smoothed log map by heat diffusion (pipelines/logmap.hpp; thesis §6.5-6.6).
#include "pipelines/logmap.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/mesh_operators.hpp"
#include "kernels/mesh_topology.hpp"
#include "kernels/solve_full.hpp"
#include "kernels/solve_plan.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

inline double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void check_outputs(const LogMapOutput& out, size_t np) {
  if (out.distance.size() != np || out.angle.size() != np || out.u.size() != np || out.v.size() != np)
    fail(ErrorCode::BadUsage, "log map: every output span needs one entry per patch vertex (" + std::to_string(np) + ")");
}

}  // namespace

HeatLogMap::HeatLogMap(const Mesh& m, const LogMapOptions& opt, const RunContext& ctx)
    : opt_(opt), geo_(m, opt.geodesic, ctx), x_(m.x), y_(m.y), z_(m.z) {
  const int32_t n = m.num_vertices();
  // Eq. 6.2: the mean-curvature normal where it is meaningful, the area normal
  // where it vanishes (planar regions) and at boundary vertices (where L_C p has
  // an in-plane boundary term). Oriented to the side of the face normals so that
  // the map keeps the faces' orientation.
  const std::vector<double> hn = mean_curvature_normals(m);
  const std::vector<double> an = area_weighted_normals(m);
  const Edges e = unique_edges(m);
  std::vector<uint8_t> boundary(static_cast<size_t>(n), 0);
  for (size_t k = 0; k < e.e0.size(); ++k)
    if (e.face_count[k] == 1) boundary[e.e0[k]] = boundary[e.e1[k]] = 1;
  // |H n| below 1e-8 / h means a curvature radius above 1e8 h: numerically planar.
  const double tiny = 1e-8 / geo_.mean_edge_length();
  normal_.resize(3 * static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) {
    const double* h = hn.data() + 3 * static_cast<size_t>(i);
    const double* a = an.data() + 3 * static_cast<size_t>(i);
    const double len = std::sqrt(dot3(h, h));
    double* o = normal_.data() + 3 * static_cast<size_t>(i);
    if (!boundary[i] && len > tiny && std::isfinite(len)) {
      const double s = dot3(h, a) < 0 ? -1.0 / len : 1.0 / len;
      for (int c = 0; c < 3; ++c) o[c] = h[c] * s;
    } else {
      for (int c = 0; c < 3; ++c) o[c] = a[c];
    }
  }
}

void HeatLogMap::frame(int32_t i, double n[3], double e1[3], double e2[3]) const {
  const TriangleGradients& g = geo_.gradients();
  for (int c = 0; c < 3; ++c) n[c] = normal_[3 * static_cast<size_t>(i) + c];
  // Lowest-numbered neighbour: deterministic, independent of face order.
  int32_t ref = -1;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q)
    for (int s = 0; s < 3; ++s) {
      const int32_t w = g.tri[3 * static_cast<int64_t>(g.vf_faces[q]) + s];
      if (w != i && (ref < 0 || w < ref)) ref = w;
    }
  double d[3] = {x_[ref] - x_[i], y_[ref] - y_[i], z_[ref] - z_[i]};
  const double dn = dot3(d, n);
  for (int c = 0; c < 3; ++c) d[c] -= dn * n[c];
  const double len = std::sqrt(dot3(d, d));
  for (int c = 0; c < 3; ++c) e1[c] = d[c] / len;
  e2[0] = n[1] * e1[2] - n[2] * e1[1];
  e2[1] = n[2] * e1[0] - n[0] * e1[2];
  e2[2] = n[0] * e1[1] - n[1] * e1[0];
}

// Sources S = {i} ∪ N(i) (i first, neighbours ascending) and their tangent
// vectors W_k = sum_{f ∋ i} A_f P grad(phi_k)_f, P = I - n n^T (eqs. 6.7, 6.8).
void HeatLogMap::prepare_centre(int32_t i, LogMapWorkspace& ws) const {
  const TriangleGradients& g = geo_.gradients();
  std::vector<int32_t>& S = ws.sources;
  S.clear();
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q)
    for (int s = 0; s < 3; ++s) S.push_back(g.tri[3 * static_cast<int64_t>(g.vf_faces[q]) + s]);
  std::sort(S.begin(), S.end());
  S.erase(std::unique(S.begin(), S.end()), S.end());
  S.erase(std::find(S.begin(), S.end(), i));
  S.insert(S.begin(), i);
  const size_t d = S.size();
  ws.weights.assign(3 * d, 0.0);
  const double* n = normal_.data() + 3 * static_cast<size_t>(i);
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
    const int32_t f = g.vf_faces[q];
    const double* b = g.basis.data() + 9 * static_cast<int64_t>(f);
    for (int s = 0; s < 3; ++s) {
      const int32_t w = g.tri[3 * static_cast<int64_t>(f) + s];
      const size_t k = static_cast<size_t>(std::find(S.begin(), S.end(), w) - S.begin());
      const double bn = dot3(b + 3 * s, n);
      for (int c = 0; c < 3; ++c) ws.weights[3 * k + c] += g.area[f] * (b[3 * s + c] - bn * n[c]);
    }
  }
}

// heat[row * row_stride + k] = (h_k)_j for the patch vertex j = patch[p], row = rows[p] (row = p when rows is empty).
void HeatLogMap::angles(int32_t centre, std::span<const int32_t> patch, const double* heat, int64_t row_stride,
                        std::span<const int32_t> rows, const LogMapOutput& out, LogMapAngle angle,
                        LogMapStats& st, LogMapWorkspace& ws) const {
  double n[3], e1[3], e2[3];
  frame(centre, n, e1, e2);
  const size_t d = ws.sources.size();
  // Weights in the frame: direction to j = (sum_k a_k f_k, sum_k b_k f_k).
  double a[64], b[64];
  std::vector<double> ab;
  double* pa = a;
  double* pb = b;
  if (d > 64) {
    ab.resize(2 * d);
    pa = ab.data();
    pb = ab.data() + d;
  }
  for (size_t k = 0; k < d; ++k) {
    pa[k] = dot3(ws.weights.data() + 3 * k, e1);
    pb[k] = dot3(ws.weights.data() + 3 * k, e2);
  }
  const bool use_log = angle == LogMapAngle::LogHeat;
  for (size_t p = 0; p < patch.size(); ++p) {
    double gx = 0, gy = 0;
    if (patch[p] != centre) {
      const double* f = heat + (rows.empty() ? static_cast<int64_t>(p) : rows[p]) * row_stride;
      bool plain = !use_log;
      if (use_log) {
        for (size_t k = 0; k < d; ++k) {
          if (!(f[k] > 0.0)) {
            plain = true;
            ++st.angle_fallbacks;
            gx = gy = 0;
            break;
          }
          const double l = std::log(f[k]);
          gx += pa[k] * l;
          gy += pb[k] * l;
        }
      }
      if (plain)
        for (size_t k = 0; k < d; ++k) {
          gx += pa[k] * f[k];
          gy += pb[k] * f[k];
        }
    }
    const double th = (gx == 0 && gy == 0) ? 0.0 : std::atan2(gy, gx);
    out.angle[p] = th;
    out.u[p] = out.distance[p] * std::cos(th);
    out.v[p] = out.distance[p] * std::sin(th);
  }
}

LogMapStats HeatLogMap::query(int32_t centre, std::span<const int32_t> patch, const LogMapOutput& out,
                              LogMapWorkspace& ws, LogMapAngle angle) const {
  const int32_t n = num_vertices();
  if (centre < 0 || centre >= n)
    fail(ErrorCode::BadUsage, "centre " + std::to_string(centre) + " is not a vertex (the mesh has " +
                                  std::to_string(n) + " vertices)");
  check_outputs(out, patch.size());
  PatchRegion& r = ws.geo.region;
  geo_.build_region(patch, r);
  LogMapStats st;
  try {
    const int32_t cl = r.local[centre];
    if (cl < 0 || cl >= r.patch_size)
      fail(ErrorCode::BadUsage, "the centre vertex " + std::to_string(centre) + " is not in the patch");
    prepare_centre(centre, ws);
    const std::vector<int32_t>& S = ws.sources;
    const int32_t d = static_cast<int32_t>(S.size());
    const size_t nloc = r.verts.size();
    st.sources = d;
    st.batches = (d + kLanes - 1) / kLanes;
    st.region_size = static_cast<int32_t>(nloc);
    const NumericFactor& F = geo_.heat_factor();
    const SolvePlan plan = plan_subset_solve(*F.symbolic, S, r.verts);
    ws.heat.resize(nloc * d);
    ws.out8.resize(nloc * kLanes);
    ws.rhs8.resize(static_cast<size_t>(d) * kLanes);
    for (int32_t bt = 0; bt < st.batches; ++bt) {
      std::fill(ws.rhs8.begin(), ws.rhs8.end(), 0.0);
      const int32_t k0 = bt * kLanes, lanes = std::min(kLanes, d - k0);
      for (int32_t l = 0; l < lanes; ++l) ws.rhs8[static_cast<size_t>(k0 + l) * kLanes + l] = 1.0;
      solve_planned8(F, plan, ws.rhs8, ws.out8, ws.geo.heat);
      for (size_t v = 0; v < nloc; ++v)
        for (int32_t l = 0; l < lanes; ++l) ws.heat[v * d + k0 + l] = ws.out8[v * kLanes + l];
    }
    // Distance from lane 0 (the heat from the centre).
    ws.geo.h.resize(nloc);
    for (size_t v = 0; v < nloc; ++v) ws.geo.h[v] = ws.heat[v * d];
    geo_.distance_from_heat(r, ws.geo.h, cl, out.distance, ws.geo, opt_.geodesic.poisson_rhs);
    // Patch vertex p is region row p (empty `rows`).
    angles(centre, patch, ws.heat.data(), d, {}, out, angle, st, ws);
  } catch (...) {
    geo_.release_region(r);
    throw;
  }
  geo_.release_region(r);
  return st;
}

LogMapStats HeatLogMap::query_full(int32_t centre, std::span<const int32_t> patch, const LogMapOutput& out,
                                   LogMapWorkspace& ws, LogMapAngle angle) const {
  const int32_t n = num_vertices();
  if (centre < 0 || centre >= n)
    fail(ErrorCode::BadUsage, "centre " + std::to_string(centre) + " is not a vertex (the mesh has " +
                                  std::to_string(n) + " vertices)");
  check_outputs(out, patch.size());
  bool has_centre = false;
  for (int32_t v : patch) {
    if (v < 0 || v >= n) fail(ErrorCode::BadUsage, "patch vertex " + std::to_string(v) + " is out of range");
    has_centre |= v == centre;
  }
  if (!has_centre) fail(ErrorCode::BadUsage, "the centre vertex " + std::to_string(centre) + " is not in the patch");
  prepare_centre(centre, ws);
  const int32_t d = static_cast<int32_t>(ws.sources.size());
  LogMapStats st;
  st.sources = d;
  st.batches = (d + kLanes - 1) / kLanes;
  st.region_size = n;
  const NumericFactor& F = geo_.heat_factor();
  ws.heat.resize(static_cast<size_t>(n) * d);
  ws.out8.resize(static_cast<size_t>(n) * kLanes);
  std::vector<double> work(solve_work_size(F, kLanes));
  for (int32_t bt = 0; bt < st.batches; ++bt) {
    std::fill(ws.out8.begin(), ws.out8.end(), 0.0);
    const int32_t k0 = bt * kLanes, lanes = std::min(kLanes, d - k0);
    for (int32_t l = 0; l < lanes; ++l) ws.out8[static_cast<size_t>(ws.sources[k0 + l]) * kLanes + l] = 1.0;
    solve8(F, ws.out8, work);
    for (int32_t v = 0; v < n; ++v)
      for (int32_t l = 0; l < lanes; ++l)
        ws.heat[static_cast<size_t>(v) * d + k0 + l] = ws.out8[static_cast<size_t>(v) * kLanes + l];
  }
  std::vector<double> h0(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) h0[v] = ws.heat[static_cast<size_t>(v) * d];
  ws.dist_full.resize(static_cast<size_t>(n));
  geo_.distance_from_heat_full(h0, centre, ws.dist_full, ws.geo);
  for (size_t p = 0; p < patch.size(); ++p) out.distance[p] = ws.dist_full[patch[p]];
  angles(centre, patch, ws.heat.data(), d, patch, out, angle, st, ws);
  return st;
}

int64_t count_flipped_triangles(const TriangleGradients& g, std::span<const int32_t> patch,
                                std::span<const double> u, std::span<const double> v, std::vector<int32_t>& local) {
  if (local.size() != static_cast<size_t>(g.nv)) local.assign(g.nv, -1);
  if (u.size() != patch.size() || v.size() != patch.size())
    fail(ErrorCode::BadUsage, "count_flipped_triangles: u and v need one entry per patch vertex");
  for (int32_t i : patch)
    if (i < 0 || i >= g.nv) fail(ErrorCode::BadUsage, "count_flipped_triangles: vertex " + std::to_string(i) + " out of range");
  for (size_t p = 0; p < patch.size(); ++p) local[patch[p]] = static_cast<int32_t>(p);
  int64_t flipped = 0;
  for (size_t p = 0; p < patch.size(); ++p) {
    const int32_t i = patch[p];
    for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
      const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(g.vf_faces[q]);
      // Count each face once: at its lowest-numbered corner.
      if (i != std::min({t[0], t[1], t[2]})) continue;
      const int32_t a = local[t[0]], b = local[t[1]], c = local[t[2]];
      if (a < 0 || b < 0 || c < 0) continue;
      const double area = (u[b] - u[a]) * (v[c] - v[a]) - (u[c] - u[a]) * (v[b] - v[a]);
      if (area < 0) ++flipped;
    }
  }
  for (int32_t i : patch) local[i] = -1;
  return flipped;
}

}  // namespace locus
