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

// split_to_count from m's count to `added` more: every split made, the
// count met, the topology of analyze_mesh kept.
void check_splits_to(const TriangleGrid& grid, Mesh& m, int32_t added, std::vector<int32_t>& site) {
  const Mesh before = m;
  const int32_t target = before.num_vertices() + added;
  CHECK(split_to_count(grid, m, target, site) == added);
  CHECK(m.num_vertices() == target);
  const MeshReport a = analyze_mesh(before), b = analyze_mesh(m);
  CHECK(b.manifold);
  CHECK(b.euler_characteristic == a.euler_characteristic);
  CHECK(b.components == a.components);
  CHECK(b.boundary_loops == a.boundary_loops);
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

TEST_CASE("remesh split to count: the longest edges split until the requested count, topology kept, on the input") {
  // A torus remesh (genus 1) on a finer torus input, 37 vertices short.
  const Mesh input = make_torus(96, 48);
  const TriangleGrid grid(input);
  Mesh m = make_torus(16, 8);
  const Mesh before = m;
  const int32_t target = before.num_vertices() + 37;
  std::vector<int32_t> site(static_cast<size_t>(m.num_vertices()));
  for (size_t v = 0; v < site.size(); ++v) site[v] = static_cast<int32_t>(v);
  // The coarse torus' edges (each once per triangle side) with their midpoints.
  struct Edge {
    double length, x, y, z;
  };
  std::vector<Edge> edges;
  for (int32_t f = 0; f < before.num_faces(); ++f) {
    const int32_t c[3] = {before.f0[f], before.f1[f], before.f2[f]};
    for (int k = 0; k < 3; ++k) {
      const int32_t u = c[k], w = c[(k + 1) % 3];
      edges.push_back({std::hypot(before.x[u] - before.x[w], before.y[u] - before.y[w], before.z[u] - before.z[w]),
                       0.5 * (before.x[u] + before.x[w]), 0.5 * (before.y[u] + before.y[w]),
                       0.5 * (before.z[u] + before.z[w])});
    }
  }
  double mean = 0;
  for (const Edge& e : edges) mean += e.length / static_cast<double>(edges.size());
  check_splits_to(grid, m, 37, site);
  REQUIRE(site.size() == static_cast<size_t>(target));
  for (int32_t v = before.num_vertices(); v < m.num_vertices(); ++v) {
    // On the input torus (R = 1, r = 0.4), within the fine torus' chord error.
    const double ring = std::hypot(m.x[v], m.y[v]) - 1.0;
    CHECK(std::abs(std::hypot(ring, m.z[v]) - 0.4) < 3e-3);
    CHECK(site[v] >= 0);
    CHECK(site[v] < before.num_vertices());
    // The midpoint of a longer than average edge, moved onto the input: no
    // farther from it than the midpoint is from the torus (and the chord error).
    const Edge* near = nullptr;
    double d = 1e30;
    for (const Edge& e : edges) {
      const double de = std::hypot(m.x[v] - e.x, m.y[v] - e.y, m.z[v] - e.z);
      if (de < d) d = de, near = &e;
    }
    const double off = std::abs(std::hypot(std::hypot(near->x, near->y) - 1.0, near->z) - 0.4);
    CHECK(d < off + 3e-3);
    CHECK(near->length > mean);
  }
  CHECK(split_to_count(grid, m, target - 5, site) == 0);  // already there
}

TEST_CASE("remesh split to count: boundary edges split too, the loops kept; pinned edges stay") {
  const Mesh input = make_grid(20);
  const TriangleGrid grid(input);
  Mesh m = make_grid(4);
  const Mesh before = m;
  std::vector<int32_t> site;
  check_splits_to(grid, m, 60, site);  // more than the interior edges in one pass
  for (int32_t v = 0; v < m.num_vertices(); ++v) CHECK(std::abs(m.z[v]) < 1e-12);
  Mesh p = make_grid(4);
  const std::vector<uint8_t> pinned(static_cast<size_t>(p.num_vertices()), 1);
  CHECK(split_to_count(grid, p, p.num_vertices() + 10, site, pinned) == 0);
  CHECK(p.num_vertices() == before.num_vertices());
}
