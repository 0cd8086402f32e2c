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
  const PolygonHeatGeodesic poly(m);
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
