// Tests for the remesh of an open tube cut along a seam (restricted_dual.hpp
// sharp boundary corners, cvt_remesh.hpp; thesis §3.7.1). Oracles: the turning
// angles of the constructed boundary (analytic: a 24-gon turns 15 degrees, a
// square's corners 90), each triangle's area by the cross product (computed
// here), the input's topology (kernels/mesh analyze_mesh).
#include "locus/pipelines/voronoi/cvt_remesh.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numeric>

#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/restricted_dual.hpp"
#include "triangle_area.hpp"

using namespace locus;

namespace {

// An open tube (radius r, height h, nu columns, nv rows) cut along the line
// at angle 0: column nu repeats column 0's positions as separate vertices, so
// the surface is a disk whose one boundary loop is both circles joined by the
// two coincident seam lines (the four seam ends turn 90 degrees).
Mesh make_seam_tube(int32_t nu, int32_t nv, double r, double h) {
  Mesh m;
  for (int32_t j = 0; j <= nv; ++j)
    for (int32_t i = 0; i <= nu; ++i) {
      const double a = 2 * M_PI * (i % nu) / nu;
      m.add_vertex(r * std::cos(a), r * std::sin(a), h * j / nv);
    }
  const int32_t w = nu + 1;
  for (int32_t j = 0; j < nv; ++j)
    for (int32_t i = 0; i < nu; ++i) {
      const int32_t a = j * w + i, b = a + 1, c = a + w, d = c + 1;
      m.add_triangle(a, b, d);
      m.add_triangle(a, d, c);
    }
  return m;
}

}  // namespace

TEST_CASE("remesh seam: the ends of a seam are not sharp boundary corners; a square's corners are") {
  const Mesh tube = make_seam_tube(24, 1, 0.125, 0.8);
  const MeshReport in = analyze_mesh(tube);
  REQUIRE(in.boundary_loops == 1);
  REQUIRE(in.euler_characteristic == 1);
  // Every vertex is on the loop; the circles turn 15 degrees, the seam ends 90
  // but sit at another boundary vertex's position.
  const DualTopology t = dual_topology(tube);
  REQUIRE(t.loops.size() == 1);
  CHECK(t.loops[0].size() == 50);
  CHECK(std::accumulate(t.sharp_boundary.begin(), t.sharp_boundary.end(), 0) == 0);
  const Mesh square = make_grid(4);
  const DualTopology s = dual_topology(square);
  CHECK(std::accumulate(s.sharp_boundary.begin(), s.sharp_boundary.end(), 0) == 4);
}

TEST_CASE("remesh seam: a thin seam tube remeshed with 6 sites has no zero-area triangle and keeps its topology") {
  // The shape of boeing's seam tubes (51 vertices, all on the boundary).
  const Mesh m = make_seam_tube(24, 1, 0.125, 0.8);
  RemeshOptions o;
  o.lloyd.sites = 6;
  o.lloyd.iterations = 10;
  const MeshDerived d = derive_mesh(m);
  const RemeshResult r = cvt_remesh(m, d, o, RunContext{});
  REQUIRE(r.complete);
  REQUIRE(r.remesh.num_faces() > 0);
  const double scale = 0.8 * 0.8;
  for (int32_t f = 0; f < r.remesh.num_faces(); ++f) CHECK(test::triangle_area(r.remesh, f) > 1e-6 * scale);
  const MeshReport in = analyze_mesh(m), out = analyze_mesh(r.remesh);
  CHECK(out.manifold);
  CHECK(out.components == in.components);
  CHECK(out.boundary_loops == in.boundary_loops);
  CHECK(out.euler_characteristic == in.euler_characteristic);
}
