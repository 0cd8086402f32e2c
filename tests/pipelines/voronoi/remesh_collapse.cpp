// Tests for the edge collapses to the requested vertex count
// (pipelines/include/locus/pipelines/voronoi/remesh_collapse.hpp; thesis
// §3.7.1). Oracles: the vertex count asked for, the topology of
// kernels/mesh analyze_mesh (Euler characteristic, components, boundary
// loops, manifoldness) against the input's, the distance of every vertex to
// the input's analytic surface, and the square's boundary for boundary
// vertices.
#include "locus/pipelines/voronoi/remesh_collapse.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

using namespace locus;

namespace {

void check_same_topology(const Mesh& input, const Mesh& out) {
  const MeshReport in = analyze_mesh(input), r = analyze_mesh(out);
  CHECK(r.manifold);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.non_manifold_vertices == 0);
  CHECK(r.unreferenced_vertices == 0);
  CHECK(r.components == in.components);
  CHECK(r.boundary_loops == in.boundary_loops);
  CHECK(r.euler_characteristic == in.euler_characteristic);
}

std::vector<int32_t> identity(int32_t n) {
  std::vector<int32_t> v(static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

}  // namespace

TEST_CASE("remesh collapse: a torus down to a third of its vertices keeps its genus and stays on the surface") {
  const double R = 1.0, r = 0.4;
  const Mesh input = make_torus(48, 24, R, r);
  const TriangleGrid grid(input);
  Mesh m = input;
  std::vector<int32_t> site = identity(m.num_vertices());
  const int32_t target = m.num_vertices() / 3;
  const int32_t k = collapse_to_count(input, grid, m, target, site);
  CHECK(k == input.num_vertices() - target);
  CHECK(m.num_vertices() == target);
  check_same_topology(input, m);
  // The merged vertices sit on the input's triangles: within the chord error
  // of the analytic torus (edge ~0.13, sagitta below 0.01).
  double worst = 0;
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double q = std::hypot(m.x[v], m.y[v]) - R;
    worst = std::max(worst, std::abs(std::hypot(q, m.z[v]) - r));
  }
  CHECK(worst < 0.01);
  // The sites follow the kept vertices: distinct input vertices.
  REQUIRE(site.size() == static_cast<size_t>(m.num_vertices()));
  CHECK(std::set<int32_t>(site.begin(), site.end()).size() == site.size());
}

TEST_CASE("remesh collapse: a square keeps its boundary loop on the square's sides; nothing to do at the count") {
  const Mesh input = make_grid(16);  // the unit square, z = 0
  const TriangleGrid grid(input);
  Mesh m = input;
  std::vector<int32_t> site;  // empty: nothing to follow
  CHECK(collapse_to_count(input, grid, m, m.num_vertices(), site) == 0);
  CHECK(m.num_vertices() == input.num_vertices());
  const int32_t target = 80;
  collapse_to_count(input, grid, m, target, site);
  CHECK(m.num_vertices() == target);
  CHECK(site.empty());
  check_same_topology(input, m);
  const auto loops = boundary_loops(m);
  REQUIRE(loops.size() == 1);
  for (int32_t v : loops[0]) {
    const double d = std::min({m.x[v], 1 - m.x[v], m.y[v], 1 - m.y[v]});
    CHECK(std::abs(d) < 1e-12);
  }
  // The four corners stay: a corner turns most, its boundary edges keep it.
  int corners = 0;
  for (int32_t v : loops[0])
    corners += (std::abs(m.x[v] - 0.5) > 0.5 - 1e-12) && (std::abs(m.y[v] - 0.5) > 0.5 - 1e-12);
  CHECK(corners == 4);
}

TEST_CASE("remesh collapse: an icosahedron cannot go below a closed mesh's fewest vertices") {
  const Mesh input = make_icosphere(0);
  const TriangleGrid grid(input);
  Mesh m = input;
  std::vector<int32_t> site;
  collapse_to_count(input, grid, m, 1, site);
  CHECK(m.num_vertices() >= 4);
  check_same_topology(input, m);
}
