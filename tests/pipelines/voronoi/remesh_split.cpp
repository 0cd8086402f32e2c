// Tests for the edge splits at thin triangles
// (pipelines/include/locus/pipelines/voronoi/remesh_split.hpp; thesis
// §3.7.1). Oracles: the topology of kernels/mesh analyze_mesh against the
// input's, the vertex and triangle counts one split adds, the new vertex at
// the midpoint of the thin triangle's longest edge (computed here from the
// coordinates) on the input plane, the budget.
#include "locus/pipelines/voronoi/remesh_split.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

using namespace locus;

namespace {

// A flat fan: six equilateral triangles around a center.
Mesh thin_fan() {
  Mesh r;
  r.add_vertex(0.5, 0.5, 0);
  for (int k = 0; k < 6; ++k) r.add_vertex(0.5 + 0.4 * std::cos(k * M_PI / 3), 0.5 + 0.4 * std::sin(k * M_PI / 3), 0);
  for (int k = 0; k < 6; ++k) r.add_triangle(0, 1 + k, 1 + (k + 1) % 6);
  return r;
}

}  // namespace

TEST_CASE("remesh split: the thin triangle's longest interior edge splits at its midpoint; topology and budget kept") {
  const Mesh input = make_grid(10);  // the unit square, z = 0
  const TriangleGrid grid(input);
  Mesh m = thin_fan();
  m.x[2] = 0.5 + 0.38;  // vertex 2 next to vertex 1 (0.9, 0.5):
  m.y[2] = 0.5 + 0.02;  // triangle (0, 1, 2) has a ~3 degree angle at the center
  std::vector<int32_t> site = {10, 11, 12, 13, 14, 15, 16};
  const Mesh before = m;
  CHECK(split_thin(grid, m, 25, 0, site) == 0);  // no budget
  CHECK(m.num_vertices() == before.num_vertices());
  const int32_t k = split_thin(grid, m, 25, 1, site);
  REQUIRE(k == 1);
  CHECK(m.num_vertices() == before.num_vertices() + 1);
  CHECK(m.num_faces() == before.num_faces() + 2);
  const MeshReport a = analyze_mesh(before), b = analyze_mesh(m);
  CHECK(b.manifold);
  CHECK(b.euler_characteristic == a.euler_characteristic);
  CHECK(b.boundary_loops == a.boundary_loops);
  // The thinnest triangle's longest edge in two triangles: 0-1 or 0-2 (the
  // boundary edge 1-2 is the shortest); the new vertex is its midpoint.
  const int32_t v = m.num_vertices() - 1;
  const double d1 = std::hypot(before.x[1] - 0.5, before.y[1] - 0.5), d2 = std::hypot(before.x[2] - 0.5, before.y[2] - 0.5);
  const int32_t far = d1 > d2 ? 1 : 2;
  CHECK(m.x[v] == doctest::Approx(0.5 * (0.5 + before.x[far])));
  CHECK(m.y[v] == doctest::Approx(0.5 * (0.5 + before.y[far])));
  CHECK(m.z[v] == 0);
  REQUIRE(site.size() == static_cast<size_t>(m.num_vertices()));
  CHECK((site.back() == 10 || site.back() == 10 + far));
}

TEST_CASE("remesh split: nothing below the angle, nothing split") {
  const Mesh input = make_grid(10);
  const TriangleGrid grid(input);
  Mesh m = thin_fan();  // equilateral triangles: 60 degrees
  std::vector<int32_t> site;
  CHECK(split_thin(grid, m, 25, 100, site) == 0);
  CHECK(m.num_vertices() == 7);
  CHECK(site.empty());
}
