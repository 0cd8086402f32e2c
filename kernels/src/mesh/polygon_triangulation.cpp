// Ear clipping of polygon faces (kernels/include/locus/kernels/mesh/polygon_triangulation.hpp).
#include "locus/kernels/mesh/polygon_triangulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "locus/error.hpp"

namespace locus {

namespace {

using P2 = std::array<double, 2>;

double cross2(const P2& o, const P2& a, const P2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// The corners in 2D coordinates of the best-fit plane (counter-clockwise),
// and a length scale for tolerances. Throws when the corners are collinear;
// `zero_area`: the Newell normal vanished (projected on a plane of three corners).
std::vector<P2> project_to_plane(std::span<const std::array<double, 3>> c, const std::string& where, double& scale,
                                 bool& zero_area) {
  const size_t k = c.size();
  // Newell normal, about the first corner (fewer cancellations far from the origin).
  double n[3] = {0, 0, 0}, perimeter2 = 0;
  for (size_t i = 0; i < k; ++i) {
    const auto& a = c[i];
    const auto& b = c[(i + 1) % k];
    const double ay = a[1] - c[0][1], az = a[2] - c[0][2], ax = a[0] - c[0][0];
    const double by = b[1] - c[0][1], bz = b[2] - c[0][2], bx = b[0] - c[0][0];
    n[0] += (ay - by) * (az + bz);
    n[1] += (az - bz) * (ax + bx);
    n[2] += (ax - bx) * (ay + by);
    perimeter2 += (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
  }
  double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  scale = std::sqrt(perimeter2 / static_cast<double>(k));
  const bool flat = std::isfinite(len) && len > 1e-12 * perimeter2;
  if (!flat) {
    // No net area: collinear corners, or a bow-tie whose lobes cancel. Any
    // plane through three spread corners tells them apart (check_simple then
    // names the crossing edges).
    for (size_t i = 1; i < k; ++i)
      for (size_t j = i + 1; j < k; ++j) {
        const double a[3] = {c[i][0] - c[0][0], c[i][1] - c[0][1], c[i][2] - c[0][2]};
        const double b[3] = {c[j][0] - c[0][0], c[j][1] - c[0][1], c[j][2] - c[0][2]};
        const double x[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        const double l = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (l > len || !std::isfinite(len)) {
          len = l;
          n[0] = x[0], n[1] = x[1], n[2] = x[2];
        }
      }
    if (!std::isfinite(len) || !(len > 1e-12 * perimeter2))
      fail(ErrorCode::BadInput, where + " (" + std::to_string(k) +
                                    " corners) has no area: its corners are collinear or coincide; cannot triangulate it");
  }
  zero_area = !flat;
  const double nz[3] = {n[0] / len, n[1] / len, n[2] / len};
  // u: the coordinate axis least aligned with the normal, made orthogonal to it; v = n x u.
  int axis = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(nz[d]) < std::abs(nz[axis])) axis = d;
  double u[3] = {0, 0, 0};
  u[axis] = 1;
  const double un = u[0] * nz[0] + u[1] * nz[1] + u[2] * nz[2];
  for (int d = 0; d < 3; ++d) u[d] -= un * nz[d];
  const double ul = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (double& x : u) x /= ul;
  const double v[3] = {nz[1] * u[2] - nz[2] * u[1], nz[2] * u[0] - nz[0] * u[2], nz[0] * u[1] - nz[1] * u[0]};
  std::vector<P2> p(k);
  for (size_t i = 0; i < k; ++i) {
    const double d[3] = {c[i][0] - c[0][0], c[i][1] - c[0][1], c[i][2] - c[0][2]};
    p[i] = {d[0] * u[0] + d[1] * u[1] + d[2] * u[2], d[0] * v[0] + d[1] * v[1] + d[2] * v[2]};
  }
  return p;
}

// Segments ab and cd intersect (touching included), with tolerance eps on the
// orientation tests and tol on the coordinates.
bool segments_meet(const P2& a, const P2& b, const P2& c, const P2& d, double eps, double tol) {
  const double d1 = cross2(a, b, c), d2 = cross2(a, b, d), d3 = cross2(c, d, a), d4 = cross2(c, d, b);
  if (((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) && ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps)))
    return true;
  auto on = [&](const P2& p, const P2& q, const P2& r, double o) {  // r on segment pq
    return std::abs(o) <= eps && r[0] >= std::min(p[0], q[0]) - tol && r[0] <= std::max(p[0], q[0]) + tol &&
           r[1] >= std::min(p[1], q[1]) - tol && r[1] <= std::max(p[1], q[1]) + tol;
  };
  return on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4);
}

void check_simple(const std::vector<P2>& p, double scale, const std::string& where) {
  const size_t k = p.size();
  const double eps = 1e-12 * scale * scale;
  for (size_t i = 0; i < k; ++i)
    for (size_t j = i + 1; j < k; ++j)
      if (std::abs(p[i][0] - p[j][0]) <= 1e-12 * scale && std::abs(p[i][1] - p[j][1]) <= 1e-12 * scale)
        fail(ErrorCode::BadInput, where + ": corners " + std::to_string(i) + " and " + std::to_string(j) +
                                      " lie at one point; cannot triangulate it");
  for (size_t i = 0; i < k; ++i)
    for (size_t j = i + 1; j < k; ++j) {
      if (j == i + 1 || (i == 0 && j == k - 1)) continue;  // adjacent edges share a corner
      if (segments_meet(p[i], p[(i + 1) % k], p[j], p[(j + 1) % k], eps, 1e-12 * scale))
        fail(ErrorCode::BadInput, where + ": its edges " + std::to_string(i) + "-" + std::to_string((i + 1) % k) +
                                      " and " + std::to_string(j) + "-" + std::to_string((j + 1) % k) +
                                      " cross (a self-intersecting polygon); cannot triangulate it");
    }
}

// Smallest angle of triangle abc (radians).
double min_angle(const P2& a, const P2& b, const P2& c) {
  const double la = std::hypot(b[0] - c[0], b[1] - c[1]), lb = std::hypot(a[0] - c[0], a[1] - c[1]),
               lc = std::hypot(a[0] - b[0], a[1] - b[1]);
  auto angle = [](double opp, double s1, double s2) {
    return std::acos(std::clamp((s1 * s1 + s2 * s2 - opp * opp) / (2 * s1 * s2), -1.0, 1.0));
  };
  return std::min({angle(la, lb, lc), angle(lb, la, lc), angle(lc, la, lb)});
}

}  // namespace

std::vector<std::array<int32_t, 3>> triangulate_polygon(std::span<const std::array<double, 3>> corners,
                                                         const std::string& where) {
  const size_t k = corners.size();
  if (k < 3) fail(ErrorCode::BadInput, where + " has " + std::to_string(k) + " corners; a face needs at least 3");
  if (k == 3) return {{0, 1, 2}};
  double scale = 0;
  bool zero_area = false;
  const std::vector<P2> p = project_to_plane(corners, where, scale, zero_area);
  check_simple(p, scale, where);
  if (zero_area)
    fail(ErrorCode::BadInput, where + " (" + std::to_string(k) + " corners) encloses no area; cannot triangulate it");
  const double eps = 1e-12 * scale * scale;
  std::vector<int32_t> ring(k);
  for (size_t i = 0; i < k; ++i) ring[i] = static_cast<int32_t>(i);
  std::vector<std::array<int32_t, 3>> tris;
  tris.reserve(k - 2);
  while (ring.size() > 3) {
    const size_t r = ring.size();
    size_t best = r;
    double best_angle = -1;
    for (size_t i = 0; i < r; ++i) {
      const P2 &a = p[ring[(i + r - 1) % r]], &b = p[ring[i]], &c = p[ring[(i + 1) % r]];
      if (!(cross2(a, b, c) > eps)) continue;  // reflex or straight corner: not an ear
      bool empty = true;
      for (size_t j = 0; j < r && empty; ++j) {
        if (j == i || j == (i + 1) % r || j == (i + r - 1) % r) continue;
        const P2& q = p[ring[j]];
        empty = !(cross2(a, b, q) >= -eps && cross2(b, c, q) >= -eps && cross2(c, a, q) >= -eps);
      }
      if (!empty) continue;
      const double quality = r <= 32 ? min_angle(a, b, c) : 1.0;
      if (quality > best_angle) {
        best_angle = quality;
        best = i;
      }
      if (r > 32) break;  // large polygons: the first ear
    }
    if (best == r)
      fail(ErrorCode::BadInput, where + " (" + std::to_string(k) + " corners): no corner can be cut off (the polygon "
                                        "is too close to degenerate); cannot triangulate it");
    tris.push_back({ring[(best + r - 1) % r], ring[best], ring[(best + 1) % r]});
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(best));
  }
  tris.push_back({ring[0], ring[1], ring[2]});
  return tris;
}

TriangulatedMesh triangulate_polygons(const Mesh& m, const std::string& name) {
  TriangulatedMesh out;
  out.mesh.x = m.x;
  out.mesh.y = m.y;
  out.mesh.z = m.z;
  out.mesh.source = m.source;
  const int32_t nv = m.num_vertices();
  std::vector<std::array<double, 3>> corners;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto fv = m.face(f);
    if (fv.size() == 3) {
      out.mesh.add_triangle(fv[0], fv[1], fv[2]);
      out.face_of.push_back(f);
      continue;
    }
    corners.clear();
    for (int32_t v : fv) {
      if (v < 0 || v >= nv)
        fail(ErrorCode::BadInput, "face " + std::to_string(f) + " of " + name + " names vertex " + std::to_string(v) +
                                      " (the mesh has " + std::to_string(nv) + ")");
      corners.push_back({m.x[v], m.y[v], m.z[v]});
    }
    for (const auto& t : triangulate_polygon(corners, "face " + std::to_string(f) + " of " + name)) {
      out.mesh.add_triangle(fv[t[0]], fv[t[1]], fv[t[2]]);
      out.face_of.push_back(f);
    }
  }
  return out;
}

}  // namespace locus
