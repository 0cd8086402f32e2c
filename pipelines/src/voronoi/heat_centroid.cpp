// Heat centroids and their quadratic refinement (pipelines/include/locus/pipelines/voronoi/heat_centroid.hpp;
// thesis §3.5 eqs. 3.24-3.29, §3.7.1 "Centroids on faces").
#include "locus/pipelines/voronoi/heat_centroid.hpp"
#include "locus/core/host_allocator.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/triangle_vector_area.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

// Vertex v's area-weighted unit normal, area_weighted_normals(m)[v] bit for
// bit: the same face vector areas summed in the same ascending face order (its
// face list), normalized alike. Computed where a fit needs it instead of held
// for every vertex (10 MB at 416k vertices through Lloyd's iterations).
std::array<double, 3> vertex_normal(const Mesh& m, const CentroidGeometry& g, int32_t v) {
  std::array<double, 3> n{0.0, 0.0, 0.0};
  for (int64_t p = g.vf_offsets[v]; p < g.vf_offsets[v + 1]; ++p) {
    const int32_t f = g.vf_faces[p];  // from f0/f1/f2: the cvt lends face_vertices out during Lloyd
    const std::array<double, 3> a = triangle_vector_area(m, m.f0[f], m.f1[f], m.f2[f]);
    n[0] += a[0];
    n[1] += a[1];
    n[2] += a[2];
  }
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (len > 0.0 && std::isfinite(len))
    for (int k = 0; k < 3; ++k) n[k] /= len;
  else
    n = {0.0, 0.0, 0.0};
  return n;
}

}  // namespace

CentroidGeometry prepare_centroid_geometry(const Mesh& m) {
  Adjacency adjacency = vertex_adjacency(m);
  CentroidGeometry g = prepare_centroid_geometry(m, adjacency);
  g.own_adj = std::move(adjacency);
  g.borrowed = nullptr;
  return g;
}

CentroidGeometry prepare_centroid_geometry(const Mesh& m, const Adjacency& adjacency) {
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": heat centroids need a triangle mesh");
  CentroidGeometry g;
  g.n = m.num_vertices();
  const int32_t nf = m.num_faces();
  g.vf_offsets.assign(static_cast<size_t>(g.n) + 1, 0);
  for (int32_t f = 0; f < nf; ++f) {
    cancel_point(f);
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) ++g.vf_offsets[v + 1];
  }
  for (int32_t v = 0; v < g.n; ++v) g.vf_offsets[v + 1] += g.vf_offsets[v];
  g.vf_faces.resize(g.vf_offsets[g.n]);
  HostVector<int64_t> fill(g.vf_offsets.begin(), g.vf_offsets.end() - 1);
  for (int32_t f = 0; f < nf; ++f) {
    cancel_point(f);
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) g.vf_faces[fill[v]++] = f;
  }
  g.borrowed = &adjacency;
  return g;
}

namespace {

// Closest point of triangle (a, b, c) to q in the plane; returns barycentric weights.
Eigen::Vector3d closest_barycentric(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                    const Eigen::Vector2d& c) {
  Eigen::Matrix2d T;
  T.col(0) = b - a;
  T.col(1) = c - a;
  const Eigen::Vector2d st = T.fullPivLu().solve(q - a);
  if (st.allFinite() && st[0] >= 0 && st[1] >= 0 && st[0] + st[1] <= 1) return {1 - st[0] - st[1], st[0], st[1]};
  // Outside: the nearest of the three edges.
  const Eigen::Vector2d P[3] = {a, b, c};
  double best = INFINITY;
  Eigen::Vector3d w(1, 0, 0);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& p0 = P[k];
    const Eigen::Vector2d& p1 = P[(k + 1) % 3];
    const Eigen::Vector2d d = p1 - p0;
    const double len2 = d.squaredNorm();
    const double s = len2 > 0 ? std::clamp((q - p0).dot(d) / len2, 0.0, 1.0) : 0.0;
    const double dist = (p0 + s * d - q).squaredNorm();
    if (dist < best) {
      best = dist;
      w.setZero();
      w[k] = 1 - s;
      w[(k + 1) % 3] = s;
    }
  }
  return w;
}

}  // namespace

namespace {

// heat(v): the heat at vertex v (any vertex the fit may read).
template <class Heat>
HeatCentroid refine_impl(const Mesh& m, const CentroidGeometry& g, const Heat& heat, int32_t c, int rings,
                         double sigma) {
  const Adjacency& adj = g.adj();
  HeatCentroid r;
  r.hottest = c;
  r.point = vertex_point(c);
  // Fit points: c and its `rings` rings; one ring more while that gives fewer than 6
  // values (six coefficients; boundary corners can have tiny rings).
  HostVector<int32_t> pts{c};
  size_t ring_begin = 0;
  for (int ring = 0; ring < rings || (pts.size() < 7 && ring < rings + 1); ++ring) {
    const size_t ring_end = pts.size();
    for (size_t k = ring_begin; k < ring_end; ++k)
      for (int64_t p = adj.offsets[pts[k]]; p < adj.offsets[pts[k] + 1]; ++p) {
        const int32_t w = adj.neighbors[p];
        if (std::find(pts.begin(), pts.end(), w) == pts.end()) pts.push_back(w);
      }
    ring_begin = ring_end;
  }
  r.fit_points = static_cast<int32_t>(pts.size());
  if (pts.size() < 6) return r;
  // Tangent frame of the area-weighted normal.
  const std::array<double, 3> nc = vertex_normal(m, g, c);
  const Eigen::Vector3d nrm(nc[0], nc[1], nc[2]);
  if (!(nrm.norm() > 0.5)) return r;
  const Eigen::Vector3d helper = std::abs(nrm[0]) < 0.9 ? Eigen::Vector3d(1, 0, 0) : Eigen::Vector3d(0, 1, 0);
  const Eigen::Vector3d e1 = nrm.cross(helper).normalized(), e2 = nrm.cross(e1);
  const Eigen::Vector3d pc(m.x[c], m.y[c], m.z[c]);
  auto project = [&](int32_t v) {
    const Eigen::Vector3d d = Eigen::Vector3d(m.x[v], m.y[v], m.z[v]) - pc;
    return Eigen::Vector2d(d.dot(e1), d.dot(e2));
  };
  // Scaled coordinates (unit radius) and heat relative to the center keep the
  // normal equations well conditioned whatever the units.
  double radius = 0;
  for (int32_t v : pts) radius = std::max(radius, project(v).norm());
  if (!(radius > 0)) return r;
  const double hc = heat(c);
  Eigen::MatrixXd A(pts.size(), 6);
  Eigen::VectorXd b(pts.size());
  for (size_t k = 0; k < pts.size(); ++k) {
    const Eigen::Vector2d q = project(pts[k]) / radius;
    A.row(k) << 1, q[0], q[1], q[0] * q[0], q[0] * q[1], q[1] * q[1];
    b[k] = heat(pts[k]) - hc;
  }
  const Eigen::VectorXd co = A.colPivHouseholderQr().solve(b);
  if (!co.allFinite()) return r;
  Eigen::Matrix2d Hs;
  Hs << 2 * co[3], co[4], co[4], 2 * co[5];
  if (!(Hs(0, 0) < 0 && Hs.determinant() > 0)) return r;  // no maximum: stay at the vertex
  Eigen::Vector2d xs = Hs.ldlt().solve(-Eigen::Vector2d(co[1], co[2])) * radius;
  if (!xs.allFinite()) return r;
  if (sigma > 0) {
    // Weighted refit centered at the first estimate: Gaussian weights of width sigma
    // times the one ring's mean projected distance, so the values near the estimate
    // dominate and the patch's asymmetry about the hottest vertex matters less.
    double r1 = 0;
    for (int64_t p = adj.offsets[c]; p < adj.offsets[c + 1]; ++p) r1 += project(adj.neighbors[p]).norm();
    r1 /= static_cast<double>(std::max<int64_t>(1, adj.offsets[c + 1] - adj.offsets[c]));
    const double inv2s2 = 1.0 / (2.0 * sigma * sigma * r1 * r1);
    for (size_t k = 0; k < pts.size(); ++k) {
      const Eigen::Vector2d d = project(pts[k]) - xs;
      const Eigen::Vector2d q = d / radius;
      const double sw = std::sqrt(std::exp(-d.squaredNorm() * inv2s2));
      A.row(k) << sw, sw * q[0], sw * q[1], sw * q[0] * q[0], sw * q[0] * q[1], sw * q[1] * q[1];
      b[k] = sw * (heat(pts[k]) - hc);
    }
    const Eigen::VectorXd cw = A.colPivHouseholderQr().solve(b);
    Eigen::Matrix2d Hw;
    Hw << 2 * cw[3], cw[4], cw[4], 2 * cw[5];
    if (cw.allFinite() && Hw(0, 0) < 0 && Hw.determinant() > 0) {  // else keep the unweighted maximizer
      const Eigen::Vector2d dx = Hw.ldlt().solve(-Eigen::Vector2d(cw[1], cw[2])) * radius;
      if (dx.allFinite()) xs += dx;
    }
  }
  // The incident triangle containing the maximizer, or the closest point on one.
  double best = INFINITY;
  for (int64_t p = g.vf_offsets[c]; p < g.vf_offsets[c + 1]; ++p) {
    const int32_t f = g.vf_faces[p];
    const int32_t fv[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const Eigen::Vector2d a = project(fv[0]), bb = project(fv[1]), cc = project(fv[2]);
    const Eigen::Vector3d w = closest_barycentric(xs, a, bb, cc);
    const double dist = (w[0] * a + w[1] * bb + w[2] * cc - xs).squaredNorm();
    if (dist < best) {
      best = dist;
      r.point = SurfacePoint{f, -1, {w[0], w[1], w[2]}};
    }
  }
  r.refined = r.point.face >= 0;
  return r;
}

}  // namespace

HeatCentroid refine_heat_maximum(const Mesh& m, const CentroidGeometry& g, std::span<const double> heat,
                                 int32_t c, int rings, double sigma) {
  if (c < 0 || c >= g.n || heat.size() != static_cast<size_t>(g.n))
    fail(ErrorCode::BadUsage, "heat centroid refinement: bad vertex or heat vector size");
  if (rings < 1 || rings > 4) fail(ErrorCode::BadUsage, "heat centroid refinement: 1 to 4 fit rings");
  if (!(sigma >= 0) || !std::isfinite(sigma)) fail(ErrorCode::BadUsage, "heat centroid refinement: sigma must be >= 0");
  return refine_impl(m, g, [&](int32_t v) { return heat[v]; }, c, rings, sigma);
}

HeatCentroid refine_heat_maximum(const Mesh& m, const CentroidGeometry& g, std::span<const double> values8,
                                 std::span<const int32_t> pos, int lane, int32_t c, int rings, double sigma) {
  if (c < 0 || c >= g.n || pos.size() != static_cast<size_t>(g.n) || lane < 0 || lane >= kLanes ||
      pos[c] < 0 || values8.size() % kLanes != 0)
    fail(ErrorCode::BadUsage, "heat centroid refinement: bad vertex, lane or position map");
  if (rings < 1 || rings > 4) fail(ErrorCode::BadUsage, "heat centroid refinement: 1 to 4 fit rings");
  if (!(sigma >= 0) || !std::isfinite(sigma)) fail(ErrorCode::BadUsage, "heat centroid refinement: sigma must be >= 0");
  return refine_impl(
      m, g,
      [&](int32_t v) { return pos[v] >= 0 ? values8[static_cast<size_t>(pos[v]) * kLanes + lane] : 0.0; }, c,
      rings, sigma);
}

HeatCentroid heat_centroid(const HeatDiffusion& H, const Mesh& m, const CentroidGeometry& g,
                           std::span<const int32_t> cell, bool refine) {
  const int32_t n = m.num_vertices();
  if (n != H.n || g.n != n) fail(ErrorCode::BadUsage, "heat centroid: operator or geometry of another mesh");
  if (cell.empty()) fail(ErrorCode::BadUsage, "heat centroid: the cell is empty");
  HostVector<double> u(n, 0.0);
  for (size_t k = 0; k < cell.size(); ++k) {
    if (cell[k] < 0 || cell[k] >= n)
      fail(ErrorCode::BadUsage, "heat centroid: cell entry " + std::to_string(k) + " is vertex " +
                                    std::to_string(cell[k]) + ", outside 0.." + std::to_string(n - 1));
    u[cell[k]] = H.mass[cell[k]];  // M chi_C (eqs. 3.7, 3.10)
  }
  solve(H.factor, u);
  const int32_t hottest = static_cast<int32_t>(std::max_element(u.begin(), u.end()) - u.begin());
  if (!refine) {
    HeatCentroid r;
    r.hottest = hottest;
    r.point = vertex_point(hottest);
    return r;
  }
  return refine_heat_maximum(m, g, u, hottest);
}

double tangential_distance(const Mesh& m, const CentroidGeometry& g, const SurfacePoint& p, const double q[3]) {
  const auto x = surface_point_position(m, p);
  double nrm[3] = {0, 0, 0};
  if (p.face >= 0) {
    const int32_t a = m.f0[p.face], b = m.f1[p.face], c = m.f2[p.face];
    const double e1[3] = {m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]};
    const double e2[3] = {m.x[c] - m.x[a], m.y[c] - m.y[a], m.z[c] - m.z[a]};
    nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
  } else {
    const std::array<double, 3> nv = vertex_normal(m, g, p.vertex);
    for (int k = 0; k < 3; ++k) nrm[k] = nv[k];
  }
  const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
  double d[3] = {q[0] - x[0], q[1] - x[1], q[2] - x[2]};
  if (len > 0) {
    const double dn = (d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]) / (len * len);
    for (int k = 0; k < 3; ++k) d[k] -= dn * nrm[k];
  }
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

void area_centroid(const Mesh& m, std::span<const int32_t> ids, std::span<const double> w, double out[3]) {
  double s = 0, sx = 0, sy = 0, sz = 0;
  for (size_t k = 0; k < ids.size(); ++k) {
    s += w[k];
    sx += w[k] * m.x[ids[k]];
    sy += w[k] * m.y[ids[k]];
    sz += w[k] * m.z[ids[k]];
  }
  out[0] = s > 0 ? sx / s : 0.0;
  out[1] = s > 0 ? sy / s : 0.0;
  out[2] = s > 0 ? sz / s : 0.0;
}

void hottest_vertices(const HeatBatch& hb, int32_t best[kLanes]) {
  double bv[kLanes];
  std::fill(best, best + kLanes, -1);
  std::fill(bv, bv + kLanes, -INFINITY);
  const int32_t cnt = hb.count();
  for (int32_t k = 0; k < cnt; ++k) {
    const double* row = hb.values.data() + static_cast<size_t>(k) * kLanes;
    const int32_t id = hb.id(k);
    for (int l = 0; l < kLanes; ++l)
      if (row[l] > bv[l] || (row[l] == bv[l] && id < best[l])) {
        bv[l] = row[l];
        best[l] = id;
      }
  }
}

}  // namespace locus
