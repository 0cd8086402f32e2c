// Tests for kernels/src/mesh/mesh_generators.cpp and kernels/src/mesh/convex_hull.cpp.
// Oracles: geometry by construction (radii, planes, analytic areas and volumes),
// Euler's formula for triangulated spheres (F = 2V - 4), exhaustive half-space
// checks of every hull face against every point, and counts of 1:4 subdivision.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "locus/kernels/mesh/convex_hull.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"

using namespace locus;

namespace {

struct Vec {
  double x, y, z;
};
Vec sub(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(Vec a) { return std::sqrt(dot(a, a)); }
Vec P(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }
Vec face_normal(const Mesh& m, int32_t f) {  // twice the area times the unit normal
  return cross(sub(P(m, m.f1[f]), P(m, m.f0[f])), sub(P(m, m.f2[f]), P(m, m.f0[f])));
}
Vec centroid(const Mesh& m, int32_t f) {
  const Vec a = P(m, m.f0[f]), b = P(m, m.f1[f]), c = P(m, m.f2[f]);
  return {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
}
// Volume enclosed by a closed triangle mesh (divergence theorem).
double volume(const Mesh& m) {
  double v = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) v += dot(P(m, m.f0[f]), cross(P(m, m.f1[f]), P(m, m.f2[f]))) / 6.0;
  return v;
}

void check_closed_sphere(const Mesh& m) {
  const MeshReport r = analyze_mesh(m);
  CHECK(r.manifold);
  CHECK(r.components == 1);
  CHECK(r.boundary_loops == 0);
  CHECK(r.genus == 0);
  CHECK(r.degenerate_faces == 0);
  CHECK(r.unreferenced_vertices == 0);
  CHECK(r.n_faces == 2 * r.n_vertices - 4);
}

// Every face plane has every point on its inner side (up to rounding of the test).
void check_all_points_inside(const Mesh& m) {
  int64_t violations = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const Vec n = face_normal(m, f), a = P(m, m.f0[f]);
    const double tol = 1e-13 * norm(n);
    for (int32_t v = 0; v < m.num_vertices(); ++v)
      if (dot(n, sub(P(m, v), a)) > tol) ++violations;
  }
  CHECK(violations == 0);
}

}  // namespace

TEST_CASE("icosphere: vertices on the sphere, faces outward") {
  for (int level : {0, 1, 3}) {
    const double r = 2.5;
    const Mesh m = make_icosphere(level, r);
    CHECK(m.num_vertices() == 10 * (1 << (2 * level)) + 2);
    for (int32_t v = 0; v < m.num_vertices(); ++v) CHECK(norm(P(m, v)) == doctest::Approx(r).epsilon(1e-14));
    for (int32_t f = 0; f < m.num_faces(); ++f) CHECK(dot(face_normal(m, f), centroid(m, f)) > 0);
    check_closed_sphere(m);
    check_all_points_inside(m);  // the icosphere is convex
  }
  CHECK_THROWS_AS(make_icosphere(-1), Error);
  CHECK_THROWS_AS(make_icosphere(2, 0.0), Error);
}

TEST_CASE("random sphere: closed genus-0 hull with every point on it") {
  for (int32_t n : {4, 5, 12, 100, 500}) {
    for (uint64_t seed : {1u, 7u}) {
      const Mesh m = make_random_sphere(n, seed);
      CHECK(m.num_vertices() == n);
      check_closed_sphere(m);
      check_all_points_inside(m);
      for (int32_t v = 0; v < m.num_vertices(); ++v) CHECK(norm(P(m, v)) == doctest::Approx(1.0).epsilon(1e-15));
      // Outward: the normal points away from the vertex mean, which is inside the hull
      // (for few points the origin need not be).
      Vec mean = {0, 0, 0};
      for (int32_t v = 0; v < n; ++v) mean = {mean.x + m.x[v] / n, mean.y + m.y[v] / n, mean.z + m.z[v] / n};
      for (int32_t f = 0; f < m.num_faces(); ++f) CHECK(dot(face_normal(m, f), sub(centroid(m, f), mean)) > 0);
    }
  }
  const Mesh a = make_random_sphere(300, 42), b = make_random_sphere(300, 42), c = make_random_sphere(300, 43);
  CHECK(a.x == b.x);
  CHECK(a.face_vertices == b.face_vertices);
  CHECK(a.x != c.x);
  CHECK_THROWS_AS(make_random_sphere(3, 1), Error);
}

TEST_CASE("random sphere with 20000 points: closed, volume approaches the ball's") {
  const Mesh m = make_random_sphere(20000, 5);
  CHECK(m.num_vertices() == 20000);
  check_closed_sphere(m);
  const double v = volume(m);
  CHECK(v < 4.0 / 3.0 * M_PI);
  CHECK(v > 4.0 / 3.0 * M_PI * (1 - 2e-3));
}

TEST_CASE("convex hull of a 3x3x3 lattice: degenerate input, exact answer") {
  std::vector<int64_t> x, y, z;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k) {
        x.push_back(i * 1000);
        y.push_back(j * 1000);
        z.push_back(k * 1000);
      }
  const std::vector<int32_t> tri = convex_hull_3d(x, y, z);
  Mesh m;
  for (size_t i = 0; i < x.size(); ++i) m.add_vertex(x[i] * 1e-3, y[i] * 1e-3, z[i] * 1e-3);
  for (size_t t = 0; t < tri.size(); t += 3) m.add_triangle(tri[t], tri[t + 1], tri[t + 2]);
  CHECK(volume(m) == doctest::Approx(8.0).epsilon(1e-14));
  check_all_points_inside(m);
  const MeshReport r = analyze_mesh(m);
  CHECK(r.manifold);
  CHECK(r.boundary_loops == 0);
  CHECK(r.euler_characteristic == 2);
  std::vector<int32_t> corner_hits(x.size(), 0);
  for (int32_t v : tri) corner_hits[v] = 1;
  CHECK(corner_hits[13] == 0);  // the center is inside
  for (int32_t c : {0, 2, 6, 8, 18, 20, 24, 26}) CHECK(corner_hits[c] == 1);
  // Coplanar and too few points are rejected.
  CHECK_THROWS_AS(convex_hull_3d(std::vector<int64_t>{0, 1, 0, 1}, std::vector<int64_t>{0, 0, 1, 1},
                                 std::vector<int64_t>{0, 0, 0, 0}),
                  Error);
  CHECK_THROWS_AS(convex_hull_3d(std::vector<int64_t>{0, 1, 0}, std::vector<int64_t>{0, 0, 1},
                                 std::vector<int64_t>{0, 0, 0}),
                  Error);
}

TEST_CASE("orient3d_exact decides nearly coplanar points correctly") {
  const int64_t big = int64_t(1) << 52;
  const int64_t a[3] = {-big, -big, 0}, b[3] = {big, -big, 0}, c[3] = {-big, big, 0};
  const int64_t up[3] = {big - 7, big - 3, 1}, on[3] = {big - 7, big - 3, 0}, down[3] = {big, big, -1};
  CHECK(orient3d_exact(a, b, c, up) == 1);
  CHECK(orient3d_exact(a, b, c, on) == 0);
  CHECK(orient3d_exact(a, b, c, down) == -1);
  // A plane tilted by one unit over 2^53: determinants around 2^105, where doubles alone
  // cannot separate the cases.
  const int64_t t1[3] = {-big, -big, 0}, t2[3] = {big, -big, 1}, t3[3] = {-big, big, 0};
  const int64_t q_on[3] = {big, big, 1}, q_above[3] = {big, big, 2}, q_below[3] = {big, big, 0};
  CHECK(orient3d_exact(t1, t2, t3, q_on) == 0);
  CHECK(orient3d_exact(t1, t2, t3, q_above) == 1);
  CHECK(orient3d_exact(t1, t2, t3, q_below) == -1);
}

TEST_CASE("torus: vertices on the torus, faces outward, quad torus has 4-gons") {
  const double R = 1.5, r = 0.5;
  const Mesh m = make_torus(16, 9, R, r);
  CHECK(m.num_vertices() == 144);
  CHECK(m.num_faces() == 288);
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    CHECK(std::hypot(std::hypot(m.x[v], m.y[v]) - R, m.z[v]) == doctest::Approx(r).epsilon(1e-14));
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const Vec c = centroid(m, f);
    const double rho = std::hypot(c.x, c.y);
    const Vec core = {R * c.x / rho, R * c.y / rho, 0.0};
    CHECK(dot(face_normal(m, f), sub(c, core)) > 0);
  }
  const Mesh q = make_quad_torus(16, 9, R, r);
  CHECK(q.num_faces() == 144);
  CHECK_FALSE(q.is_triangle_mesh());
  for (int32_t f = 0; f < q.num_faces(); ++f) CHECK(q.face(f).size() == 4);
  CHECK(q.x == m.x);
  CHECK_THROWS_AS(make_torus(2, 5), Error);
  CHECK_THROWS_AS(make_torus(5, 5, 1.0, 1.0), Error);
}

TEST_CASE("grid: unit square, positive triangles, seeded flips") {
  for (double fraction : {0.0, 0.4, 1.0}) {
    const int32_t n = 8;
    const Mesh m = make_grid(n, fraction, 11);
    CHECK(m.num_vertices() == 81);
    CHECK(m.num_faces() == 128);
    double area = 0;
    int32_t flipped = 0;
    for (int32_t f = 0; f < m.num_faces(); ++f) {
      const Vec nrm = face_normal(m, f);
      CHECK(nrm.z == doctest::Approx(1.0 / (n * n)).epsilon(1e-12));  // positive, area 1/(2n^2)
      area += 0.5 * nrm.z;
      for (double z : {m.z[m.f0[f]], m.z[m.f1[f]], m.z[m.f2[f]]}) CHECK(z == 0.0);
    }
    for (int32_t s = 0; s < n * n; ++s) {  // a square's first triangle uses the b-d diagonal iff flipped
      const int32_t a = m.f0[2 * s], c = m.f2[2 * s];
      flipped += (c - a == n + 1);
    }
    CHECK(area == doctest::Approx(1.0).epsilon(1e-14));
    if (fraction == 0.0) CHECK(flipped == 0);
    if (fraction == 1.0) CHECK(flipped == n * n);
    if (fraction == 0.4) {
      CHECK(flipped > 10);
      CHECK(flipped < 45);
    }
  }
  CHECK(make_grid(6, 0.5, 3).face_vertices == make_grid(6, 0.5, 3).face_vertices);
  CHECK(make_grid(6, 0.5, 3).face_vertices != make_grid(6, 0.5, 4).face_vertices);
}

TEST_CASE("disk: planar, positive, roughly equilateral, area of the inscribed polygon") {
  for (double fraction : {0.0, 0.3}) {
    const int32_t rings = 10;
    const Mesh m = make_disk(rings, fraction, 5);
    CHECK(m.num_vertices() == 1 + 3 * rings * (rings + 1));
    CHECK(m.num_faces() == 6 * rings * rings);
    double area = 0, min_angle = M_PI;
    for (int32_t f = 0; f < m.num_faces(); ++f) {
      const Vec nrm = face_normal(m, f);
      CHECK(nrm.z > 0);
      area += 0.5 * nrm.z;
      const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
      for (int k = 0; k < 3; ++k) {
        const Vec e1 = sub(P(m, v[(k + 1) % 3]), P(m, v[k])), e2 = sub(P(m, v[(k + 2) % 3]), P(m, v[k]));
        min_angle = std::min(min_angle, std::acos(dot(e1, e2) / (norm(e1) * norm(e2))));
      }
    }
    for (int32_t v = 0; v < m.num_vertices(); ++v) CHECK(m.z[v] == 0.0);
    const double n = 6.0 * rings;
    CHECK(area == doctest::Approx(0.5 * n * std::sin(2 * M_PI / n)).epsilon(1e-13));
    if (fraction == 0.0) CHECK(min_angle > 40.0 * M_PI / 180.0);
    const MeshReport r = analyze_mesh(m);
    CHECK(r.manifold);
    CHECK(r.boundary_loops == 1);
    CHECK(r.degenerate_faces == 0);
  }
  CHECK(make_disk(8, 0.5, 2).face_vertices != make_disk(8, 0.0, 2).face_vertices);
  CHECK(make_disk(8, 0.5, 2).face_vertices == make_disk(8, 0.5, 2).face_vertices);
}

TEST_CASE("1:4 midpoint subdivision: V' = V + E, F' = 4F, midpoints, area kept") {
  const Mesh g = make_grid(3, 0.5, 2);
  const int64_t E = static_cast<int64_t>(unique_edges(g).e0.size());
  const Mesh s = subdivide_midpoint(g, 1);
  CHECK(s.num_vertices() == g.num_vertices() + E);
  CHECK(s.num_faces() == 4 * g.num_faces());
  for (int32_t v = 0; v < g.num_vertices(); ++v) CHECK(s.x[v] == g.x[v]);
  const Edges e = unique_edges(g);
  for (int64_t k = 0; k < E; ++k) {
    CHECK(s.x[g.num_vertices() + k] == doctest::Approx(0.5 * (g.x[e.e0[k]] + g.x[e.e1[k]])));
    CHECK(s.y[g.num_vertices() + k] == doctest::Approx(0.5 * (g.y[e.e0[k]] + g.y[e.e1[k]])));
  }
  double area = 0;
  for (int32_t f = 0; f < s.num_faces(); ++f) {
    CHECK(face_normal(s, f).z > 0);
    area += 0.5 * face_normal(s, f).z;
  }
  CHECK(area == doctest::Approx(1.0).epsilon(1e-14));
  const Mesh s2 = subdivide_midpoint(make_torus(5, 4), 2);
  const MeshReport r = analyze_mesh(s2);
  CHECK(r.n_faces == 40 * 16);
  CHECK(r.genus == 1);
  CHECK(r.manifold);
  CHECK(subdivide_midpoint(g, 0).face_vertices == g.face_vertices);
  Mesh q = make_quad_torus(4, 4);
  q.source = "quads.obj";
  CHECK_THROWS_WITH_AS(subdivide_midpoint(q, 1), "quads.obj: face 0 has 4 vertices; 1:4 midpoint subdivision needs triangles",
                       Error);
}
