// Tests for the remesh's pull towards its input's farthest vertices
// (pipelines/include/locus/pipelines/voronoi/remesh_fidelity.hpp; thesis
// §3.7.1). Oracles: a finely triangulated hexagonal cone and a six-triangle
// fan remesh on its rim whose center misses the apex (the spike); the
// spike's distance to the remesh by brute force
// over the fan's triangles (closest point on a triangle from its own
// coordinates here, not the pipeline's grid), the fan's angles from its
// coordinates, the boundary vertices' positions.
#include "locus/pipelines/voronoi/remesh_fidelity.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "brute_distance.hpp"

using namespace locus;

namespace {

using namespace locus::test;

P3 rim(int k) { return {0.5 + 0.4 * std::cos(k * M_PI / 3), 0.5 + 0.4 * std::sin(k * M_PI / 3), 0}; }

// A hexagonal cone: six triangles from the apex to the rim (radius 0.4 around
// (0.5, 0.5), z = 0), each split into n x n small ones (a triangle soup).
Mesh cone(const P3& apex, int n) {
  Mesh m;
  for (int k = 0; k < 6; ++k) {
    const P3 a = apex, b = rim(k), c = rim(k + 1);
    const int32_t base = m.num_vertices();
    auto id = [&](int i, int j) { return base + i * (n + 1) - i * (i - 1) / 2 + j; };  // i + j <= n
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
        m.add_vertex(a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]), a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]),
                     a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]));
      }
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        m.add_triangle(id(i, j), id(i + 1, j), id(i, j + 1));
        if (i + j + 1 < n) m.add_triangle(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
  }
  return m;
}

// Six triangles around a center at (cx, cy, cz) to the cone's rim, which is
// the fan's boundary.
Mesh fan(const P3& center) {
  Mesh r;
  r.add_vertex(center[0], center[1], center[2]);
  for (int k = 0; k < 6; ++k) r.add_vertex(rim(k)[0], rim(k)[1], rim(k)[2]);
  for (int k = 0; k < 6; ++k) r.add_triangle(0, 1 + k, 1 + (k + 1) % 6);
  return r;
}

}  // namespace

TEST_CASE("remesh fidelity: a free vertex moves onto the apex the remesh missed; the boundary stays") {
  const P3 spike = {0.5, 0.5, 0.1};
  const Mesh input = cone(spike, 8);
  const TriangleGrid grid(input);
  // The center 0.06 off the apex, on the cone.
  const ClosestPoint c = grid.closest({0.56, 0.5, 0.1});
  Mesh m = fan(c.point);
  const Mesh before = m;
  const double d0 = distance_to(m, spike);
  CHECK(d0 > 0.01);
  CHECK(pull_to_input(input, grid, m) >= 1);
  CHECK(distance_to(m, spike) < 1e-9);  // the center on the apex: the remesh is the cone
  CHECK(m.x[0] == doctest::Approx(0.5));
  CHECK(m.y[0] == doctest::Approx(0.5));
  CHECK(m.z[0] == doctest::Approx(0.1));
  for (int32_t v = 1; v < m.num_vertices(); ++v) {  // the rim (boundary) did not move
    CHECK(m.x[v] == before.x[v]);
    CHECK(m.y[v] == before.y[v]);
    CHECK(m.z[v] == before.z[v]);
  }
}

TEST_CASE("remesh fidelity: no pull takes a ring angle below min(its smallest, 30 degrees)") {
  // The apex 0.1 from rim vertex (0.9, 0.5): a center there leaves
  // triangles far below 30 degrees.
  const P3 spike = {0.8, 0.5, 0.05};
  const Mesh input = cone(spike, 8);
  const TriangleGrid grid(input);
  Mesh m = fan(grid.closest({0.5, 0.5, 0.05}).point);
  const double a0 = smallest_angle_deg(m), d0 = distance_to(m, spike);
  REQUIRE(a0 > 45);
  REQUIRE(d0 > 0.01);
  pull_to_input(input, grid, m);
  CHECK(smallest_angle_deg(m) >= 30 - 1e-6);
  CHECK(distance_to(m, spike) <= d0 + 1e-12);  // never farther
  // Without the floor (and the angle budget) the same pull goes below 30
  // degrees: the floor is what held it.
  RemeshFidelityOptions loose;
  loose.keep_deg = 0;
  loose.budget_deg = 90;
  loose.mean_floor_deg = 0;
  Mesh free = fan(grid.closest({0.5, 0.5, 0.05}).point);
  CHECK(pull_to_input(input, grid, free, loose) >= 1);
  CHECK(smallest_angle_deg(free) < 30);
  CHECK(distance_to(free, spike) < d0);
  RemeshFidelityOptions off;
  off.passes = 0;
  Mesh same = fan(grid.closest({0.5, 0.5, 0.05}).point);
  const double x0 = same.x[0];
  CHECK(pull_to_input(input, grid, same, off) == 0);
  CHECK(same.x[0] == x0);
}
