// Flips of a remesh (pipelines/src/voronoi/remesh_flips.hpp) on a flat square
// with a collinear triangle: without features it flips away; with a feature
// curve along y = 0.5, the edge that skips a curve vertex flips and the
// curve's own edges stay; a free vertex lying on a feature edge joins the
// curve and the edge flips. Checked against the square's known connectivity
// and coordinates.
#include <doctest/doctest.h>

#include <array>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/remesh_optimize.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

using namespace locus;

namespace {

constexpr int32_t A = 0, B = 1, C = 2, D = 3, P = 4, Q = 5, R = 6;

// The unit square's corners A-D and P, Q, R on y = 0.5: (P, R, Q) has zero
// area, Q on the segment P-R.
Mesh collinear_square() {
  Mesh r;
  for (const auto& p : std::vector<std::array<double, 2>>{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.25, 0.5}, {0.5, 0.5}, {0.75, 0.5}})
    r.add_vertex(p[0], p[1], 0);
  for (const auto& t : std::vector<std::array<int32_t, 3>>{
           {A, B, R}, {A, R, P}, {P, R, Q}, {Q, R, C}, {Q, C, D}, {P, Q, D}, {A, P, D}, {B, C, R}})
    r.add_triangle(t[0], t[1], t[2]);
  return r;
}

bool has_edge(const Mesh& r, int32_t u, int32_t w) {
  for (int32_t f = 0; f < r.num_faces(); ++f) {
    const int32_t t[3] = {r.f0[f], r.f1[f], r.f2[f]};
    for (int k = 0; k < 3; ++k)
      if ((t[k] == u && t[(k + 1) % 3] == w) || (t[k] == w && t[(k + 1) % 3] == u)) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("remesh optimization: a collinear (degenerate) triangle is flipped away; topology and surface kept") {
  const Mesh input = make_grid(10);  // the unit square, z = 0
  Mesh r = collinear_square();
  const MeshReport before = analyze_mesh(r);
  REQUIRE(before.manifold);
  REQUIRE(remesh_stats(input, r, false).min_angle_deg == 0);
  const TriangleGrid grid(input);
  const RemeshOptimizeStats st = optimize_remesh(input, grid, r, RemeshOptimizeOptions{2});
  CHECK(st.flips >= 1);
  const MeshReport after = analyze_mesh(r);
  CHECK(after.manifold);
  CHECK(after.euler_characteristic == before.euler_characteristic);
  CHECK(after.boundary_loops == 1);
  CHECK(after.degenerate_faces == 0);
  CHECK(remesh_stats(input, r, false).min_angle_deg > 10);
  for (int32_t v = 0; v < r.num_vertices(); ++v) {  // on the input; the corners stay
    CHECK(r.z[v] == 0);
    CHECK((r.x[v] >= 0 && r.x[v] <= 1 && r.y[v] >= 0 && r.y[v] <= 1));
  }
  CHECK((r.x[C] == 1 && r.y[C] == 1));
}

// P, Q, R pinned on the curve: P-Q and Q-R are its edges and stay; P-R skips
// Q, is no feature edge, and flips (the rule had kept every edge between two
// pinned vertices, and with them a 0-degree triangle).
TEST_CASE("remesh flips: on a feature curve, the edge skipping a vertex flips; the curve's edges stay") {
  const Mesh input = make_grid(10);
  Mesh r = collinear_square();
  RemeshOptimizeOptions o{2};
  o.pinned = {0, 0, 0, 0, 1, 1, 1};
  o.slides = {FeatureCurve{{{0, 0.5, 0}, {1, 0.5, 0}}, false, {P, Q, R}, {0.25, 0.5, 0.75}}};
  const TriangleGrid grid(input);
  optimize_remesh(input, grid, r, o);
  CHECK(analyze_mesh(r).degenerate_faces == 0);
  CHECK(remesh_stats(input, r, false).min_angle_deg > 10);
  CHECK(has_edge(r, P, Q));
  CHECK(has_edge(r, Q, R));
  CHECK_FALSE(has_edge(r, P, R));
  for (int32_t v : {P, Q, R}) CHECK(r.y[v] == 0.5);  // they slide along the curve only
}

// Q free on the feature edge P-R (a vertex projected onto a convex crease
// stays there: no tangential move takes it off) joins the curve: P-R flips,
// P-Q and Q-R become the curve's edges, Q slides along it.
TEST_CASE("remesh flips: a free vertex on a feature edge joins the curve, and the edge flips") {
  const Mesh input = make_grid(10);
  Mesh r = collinear_square();
  RemeshOptimizeOptions o{2};
  o.pinned = {0, 0, 0, 0, 1, 0, 1};
  o.slides = {FeatureCurve{{{0, 0.5, 0}, {1, 0.5, 0}}, false, {P, R}, {0.25, 0.75}}};
  const TriangleGrid grid(input);
  optimize_remesh(input, grid, r, o);
  const MeshReport after = analyze_mesh(r);
  CHECK(after.degenerate_faces == 0);
  CHECK(after.euler_characteristic == 1);
  CHECK_FALSE(has_edge(r, P, R));
  CHECK(has_edge(r, P, Q));
  CHECK(has_edge(r, Q, R));
  for (int32_t v : {P, Q, R}) CHECK(r.y[v] == 0.5);
  CHECK((r.x[P] < r.x[Q] && r.x[Q] < r.x[R]));  // in their order along the curve
}
