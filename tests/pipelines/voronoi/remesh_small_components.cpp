// Tests for the one-triangle components of a remesh set to their input
// triangle (pipelines/include/locus/pipelines/voronoi/remesh_small_components.hpp;
// thesis §3.7.1). Oracles: the input's coordinates, a triangle's area by the
// cross product (computed here), the untouched larger component.
#include "locus/pipelines/voronoi/remesh_small_components.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "triangle_area.hpp"

using namespace locus;

TEST_CASE("remesh small components: a one-triangle component of zero area takes its input triangle back") {
  // The input: the unit square (a grid) and, apart, one triangle at z = 1.
  Mesh input = make_grid(4);
  const int32_t n = input.num_vertices();
  input.add_vertex(2, 0, 1);
  input.add_vertex(3, 0, 1);
  input.add_vertex(2, 1, 1);
  input.add_triangle(n, n + 1, n + 2);
  const TriangleGrid grid(input);
  // The remesh: the square as two triangles, and the triangle's two first
  // corners with the midpoint between them (collinear: zero area).
  Mesh remesh;
  for (auto [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}}) remesh.add_vertex(x, y, 0);
  remesh.add_triangle(0, 1, 2);
  remesh.add_triangle(0, 2, 3);
  remesh.add_vertex(2, 0, 1);
  remesh.add_vertex(2.5, 0, 1);
  remesh.add_vertex(3, 0, 1);
  remesh.add_triangle(4, 5, 6);
  REQUIRE(test::triangle_area(remesh, 2) == 0);
  const Mesh square = remesh;
  CHECK(restore_single_triangles(input, grid, remesh) == 1);
  CHECK(test::triangle_area(remesh, 2) == doctest::Approx(0.5));
  // The input's corners, in the input's order from the one nearest vertex 4.
  CHECK(remesh.x[4] == 2);
  CHECK(remesh.x[5] == 3);
  CHECK(remesh.x[6] == 2);
  CHECK(remesh.y[6] == 1);
  for (int32_t v = 0; v < 4; ++v) CHECK(remesh.x[v] == square.x[v]);
  CHECK(restore_single_triangles(input, grid, remesh) == 1);  // idempotent: the same positions
  CHECK(test::triangle_area(remesh, 2) == doctest::Approx(0.5));
}

TEST_CASE("remesh small components: a one-triangle remesh of a larger input component stays") {
  const Mesh input = make_grid(4);
  const TriangleGrid grid(input);
  Mesh remesh;
  remesh.add_vertex(0, 0, 0);
  remesh.add_vertex(1, 0, 0);
  remesh.add_vertex(0, 1, 0);
  remesh.add_triangle(0, 1, 2);
  CHECK(restore_single_triangles(input, grid, remesh) == 0);
  CHECK(remesh.x[1] == 1);
}
