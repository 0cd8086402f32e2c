// Heat geodesic distance on polygon meshes (pipelines/include/locus/pipelines/geodesic/polygon_heat_geodesic.hpp).
// Oracles: on a triangle mesh the polygon operators are the triangle ones
// (HeatGeodesic, same t and eps); the great-circle distance on a cube-sphere
// and the Euclidean distance on planar quad grids; and the same surfaces
// triangulated (quads split by a diagonal), which the polygon version must not
// lose to.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/geodesic/polygon_heat_geodesic.hpp"
#include "locus/pipelines/geodesic/polygon_logmap.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"

using namespace locus;

namespace {

double great_circle(const Mesh& m, int32_t a, int32_t b) {
  const double c = m.x[a] * m.x[b] + m.y[a] * m.y[b] + m.z[a] * m.z[b];
  return std::acos(std::clamp(c, -1.0, 1.0));
}

// Planar quad grid [0, 1]^2, n x n squares; triangulated: each square split by a diagonal.
Mesh quad_grid(int n, bool triangulate) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.add_vertex(static_cast<double>(i) / n, static_cast<double>(j) / n, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      if (triangulate) {
        m.add_triangle(a, b, c);
        m.add_triangle(a, c, d);
      } else {
        const int32_t q[4] = {a, b, c, d};
        m.add_face(q);
      }
    }
  return m;
}

}  // namespace

TEST_CASE("polygon heat geodesic: on a triangle mesh it is the triangle heat method") {
  const Mesh m = make_random_sphere(500, 4);
  PolygonHeatGeodesicOptions po;
  po.t_factor = HeatGeodesicOptions{}.t_factor;
  const PolygonHeatGeodesic poly(m, po);
  const HeatGeodesic tri(m);
  CHECK(poly.time() == doctest::Approx(tri.time()).epsilon(1e-12));
  std::vector<double> a(m.num_vertices()), b(m.num_vertices());
  HeatGeodesicWorkspace ws;
  poly.query_full(11, a);
  tri.query_full(11, b, ws);
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  CHECK(worst < 1e-9);
}

TEST_CASE("polygon heat geodesic: cube-sphere — great-circle distance, no worse than the triangulated mesh") {
  const int n = 16;  // 1536 quads, h ~ 0.1
  const Mesh quads = make_cube_sphere(n), tris = make_cube_sphere(n, true);
  REQUIRE(quads.num_faces() == 6 * n * n);
  REQUIRE(quads.num_vertices() == 6 * n * n + 2);
  const HeatGeodesic tri(tris);
  // The same t for both (the triangulation's mean edge counts the diagonals).
  PolygonHeatGeodesicOptions po;
  po.t_factor = HeatGeodesicOptions{}.t_factor *
                std::pow(tri.mean_edge_length() / PolygonHeatGeodesic(quads).mean_edge_length(), 2);
  const PolygonHeatGeodesic poly(quads, po);
  HeatGeodesicWorkspace ws;
  std::vector<double> dq(quads.num_vertices()), dt(tris.num_vertices());
  double eq = 0, et = 0;
  const int32_t sources[3] = {0, 500, 1234};
  for (int32_t s : sources) {
    poly.query_full(s, dq);
    tri.query_full(s, dt, ws);
    CHECK(dq[s] == 0.0);
    for (int32_t i = 0; i < quads.num_vertices(); ++i) {
      const double exact = great_circle(quads, s, i);
      eq += std::abs(dq[i] - exact) / quads.num_vertices() / 3;
      et += std::abs(dt[i] - exact) / quads.num_vertices() / 3;
    }
  }
  MESSAGE("cube-sphere " << n << ": mean |d - exact| quads " << eq << ", triangulated " << et);
  CHECK(eq < 0.03);
  CHECK(eq <= et);
}

TEST_CASE("polygon heat geodesic: planar quad grid and a mixed mesh (quads, triangles, a hexagon)") {
  const int n = 40;
  const Mesh quads = quad_grid(n, false), tris = quad_grid(n, true);
  const int32_t c = (n / 2) * (n + 1) + n / 2;
  const PolygonHeatGeodesic poly(quads);
  const HeatGeodesic tri(tris);
  HeatGeodesicWorkspace ws;
  std::vector<double> dq(quads.num_vertices()), dt(tris.num_vertices());
  poly.query_full(c, dq);
  tri.query_full(c, dt, ws);
  // Within radius 0.4 of the center (away from the boundary, where the heat
  // method's natural boundary condition bends the distance).
  auto error = [&](const Mesh& m, const std::vector<double>& d) {
    double e = 0;
    int cnt = 0;
    for (int32_t i = 0; i < m.num_vertices(); ++i) {
      const double r = std::hypot(m.x[i] - m.x[c], m.y[i] - m.y[c]);
      if (r <= 0.4) e += std::abs(d[i] - r), ++cnt;
    }
    return e / cnt;
  };
  const double eq = error(quads, dq), et = error(tris, dt);
  MESSAGE("quad grid " << n << ": mean |d - exact| quads " << eq << ", triangulated " << et);
  CHECK(eq < 0.01);
  CHECK(eq < et);  // the triangulation's diagonals bias it
  // Mixed: every other square of a row split into two triangles, two squares merged into a hexagon.
  Mesh mixed;
  mixed.x = quads.x, mixed.y = quads.y, mixed.z = quads.z;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i, b = a + 1, cc = a + n + 2, d = a + n + 1;
      if (j == 5 && i == 5) {
        const int32_t hex[6] = {a, b, b + 1, cc + 1, cc, d};  // squares (5, 5) and (6, 5)
        mixed.add_face(hex);
      } else if (j == 5 && i == 6) {
        continue;
      } else if (j % 3 == 0 && i % 2 == 0) {
        mixed.add_triangle(a, b, cc);
        mixed.add_triangle(a, cc, d);
      } else {
        const int32_t q[4] = {a, b, cc, d};
        mixed.add_face(q);
      }
    }
  const PolygonHeatGeodesic pm(mixed);
  std::vector<double> dm(mixed.num_vertices());
  pm.query_full(c, dm);
  const double em = error(mixed, dm);
  MESSAGE("mixed grid: mean |d - exact| " << em);
  CHECK(em < 0.01);
}

namespace {

// Azimuth of b around a on the unit sphere, in some tangent frame of a.
double sphere_azimuth(const Mesh& m, int32_t a, int32_t b) {
  const double n[3] = {m.x[a], m.y[a], m.z[a]};
  double r[3] = {1, 0, 0};
  if (std::abs(n[0]) > 0.9) r[0] = 0, r[1] = 1;
  const double rn = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
  double e1[3] = {r[0] - rn * n[0], r[1] - rn * n[1], r[2] - rn * n[2]};
  const double l = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (double& c : e1) c /= l;
  const double e2[3] = {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
  const double p[3] = {m.x[b], m.y[b], m.z[b]};
  return std::atan2(p[0] * e2[0] + p[1] * e2[1] + p[2] * e2[2], p[0] * e1[0] + p[1] * e1[1] + p[2] * e1[2]);
}

// Mean |angle - exact - delta| over the patch without the center, delta the best rotation.
double angle_error(const std::vector<double>& got, const std::vector<double>& exact, const std::vector<int32_t>& patch,
                   int32_t c) {
  double cs = 0, sn = 0;
  for (size_t p = 0; p < patch.size(); ++p)
    if (patch[p] != c) cs += std::cos(got[p] - exact[p]), sn += std::sin(got[p] - exact[p]);
  const double delta = std::atan2(sn, cs);
  double e = 0;
  for (size_t p = 0; p < patch.size(); ++p)
    if (patch[p] != c) e += std::abs(std::remainder(got[p] - exact[p] - delta, 2 * M_PI));
  return e / static_cast<double>(patch.size() - 1);
}

}  // namespace

TEST_CASE("polygon log map: cube-sphere and planar quad grid against the analytic map, and the triangulated mesh") {
  const int n = 16;
  const Mesh quads = make_cube_sphere(n), tris = make_cube_sphere(n, true);
  const HeatLogMap tri(tris);
  PolygonHeatGeodesicOptions po;  // the triangulation's t (its mean edge counts the diagonals)
  po.t_factor = HeatGeodesicOptions{}.t_factor *
                std::pow(tri.geodesic().mean_edge_length() / PolygonHeatGeodesic(quads).mean_edge_length(), 2);
  const PolygonLogMap poly(quads, po);
  LogMapWorkspace ws;
  double eq = 0, et = 0, dq = 0, dt = 0;
  int64_t flips = 0;
  const int32_t centers[3] = {0, 500, 1234};  // 0: a cube corner (valence 3)
  for (int32_t c : centers) {
    std::vector<int32_t> patch{c};
    for (int32_t j = 0; j < quads.num_vertices(); ++j)
      if (j != c && great_circle(quads, c, j) <= 0.8) patch.push_back(j);
    std::vector<double> exact(patch.size());
    for (size_t p = 0; p < patch.size(); ++p) exact[p] = sphere_azimuth(quads, c, patch[p]);
    const size_t k = patch.size();
    std::vector<double> d(k), a(k), u(k), v(k), d2(k), a2(k), u2(k), v2(k);
    poly.query_full(c, patch, {d, a, u, v});
    tri.query_full(c, patch, {d2, a2, u2, v2}, ws);  // (same vertex ids)
    eq += angle_error(a, exact, patch, c) / 3;
    et += angle_error(a2, exact, patch, c) / 3;
    for (size_t p = 0; p < k; ++p) {
      dq += std::abs(d[p] - great_circle(quads, c, patch[p])) / k / 3;
      dt += std::abs(d2[p] - great_circle(quads, c, patch[p])) / k / 3;
    }
    flips += count_flipped_polygons(quads, patch, u, v);
  }
  MESSAGE("cube-sphere " << n << " log map, radius 0.8: quads E_a " << eq << " E_d " << dq << "; triangulated E_a " << et
                         << " E_d " << dt << "; flipped quads " << flips);
  CHECK(eq < 0.02);
  CHECK(eq <= et);
  CHECK(dq <= dt);
  CHECK(flips == 0);
  // Planar grid: the polar angle around the center.
  const int g = 40;
  const Mesh grid = quad_grid(g, false);
  const int32_t c = (g / 2) * (g + 1) + g / 2;
  const PolygonLogMap pg(grid);
  std::vector<int32_t> patch{c};
  for (int32_t j = 0; j < grid.num_vertices(); ++j)
    if (j != c && std::hypot(grid.x[j] - grid.x[c], grid.y[j] - grid.y[c]) <= 0.4) patch.push_back(j);
  std::vector<double> exact(patch.size()), d(patch.size()), a(patch.size()), u(patch.size()), v(patch.size());
  for (size_t p = 0; p < patch.size(); ++p) exact[p] = std::atan2(grid.y[patch[p]] - grid.y[c], grid.x[patch[p]] - grid.x[c]);
  pg.query_full(c, patch, {d, a, u, v});
  const double eg = angle_error(a, exact, patch, c);
  MESSAGE("quad grid " << g << " log map: E_a " << eg << ", flipped quads " << count_flipped_polygons(grid, patch, u, v));
  CHECK(eg < 0.02);
  CHECK(count_flipped_polygons(grid, patch, u, v) == 0);
}
