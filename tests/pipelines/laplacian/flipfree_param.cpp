// Tests for pipelines/flipfree_param (thesis §2.6). Oracles: hand-made faces with
// known orientation for the face check; an orientation test written here, apart
// from the library's, on the parameterizations; Tutte/Floater (non-negative
// weights + convex boundary => every face convex and counter-clockwise); the
// boundary must sit on the unit circle at its arc-length positions.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/laplacian/flipfree_param.hpp"
#include "tests/pipelines/delaunay_fixture.hpp"

using namespace locus;

namespace {

// Faces whose corners do not all turn counter-clockwise in (u, v).
int64_t count_bad_corners(const Mesh& m, const std::vector<double>& uv) {
  int64_t bad = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto fv = m.face(f);
    const size_t d = fv.size();
    bool ok = true;
    for (size_t c = 0; c < d; ++c) {
      const int32_t a = fv[(c + d - 1) % d], b = fv[c], e = fv[(c + 1) % d];
      const double cr = (uv[2 * b] - uv[2 * a]) * (uv[2 * e + 1] - uv[2 * b + 1]) -
                        (uv[2 * b + 1] - uv[2 * a + 1]) * (uv[2 * e] - uv[2 * b]);
      if (!(cr > 0)) ok = false;
    }
    if (!ok) ++bad;
  }
  return bad;
}

// A (n+1)^2 quad grid over [-1,1]^2 lifted to a bumpy surface.
Mesh lifted_quad_grid(int n) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
      m.add_vertex(x, y, 0.4 * std::sin(2 * x) * std::cos(1.5 * y) + 0.3 * x * x);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i;
      const int32_t q[4] = {a, a + 1, a + n + 2, a + n + 1};
      m.add_face(q);
    }
  return m;
}

}  // namespace

TEST_CASE("planar face check on hand-made faces") {
  Mesh m;
  for (int i = 0; i < 4; ++i) m.add_vertex(0, 0, 0);
  const int32_t quad[4] = {0, 1, 2, 3};
  m.add_face(quad);
  std::vector<double> u{0, 1, 1, 0}, v{0, 0, 1, 1};
  auto c = check_planar_faces(m, u, v);
  CHECK(c.flipped_faces == 0);
  CHECK(c.degenerate_faces == 0);
  CHECK(c.min_corner_sin == doctest::Approx(1.0));
  u = {0, 0, 1, 1};  // same square, clockwise
  v = {0, 1, 1, 0};
  CHECK(check_planar_faces(m, u, v).flipped_faces == 1);
  u = {0, 2, 0.5, 0};  // a dart: positive area, one reflex corner
  v = {0, 0, 0.5, 2};
  c = check_planar_faces(m, u, v);
  CHECK(c.flipped_faces == 1);
  CHECK(c.first_flipped == 0);
  u = {0, 1, 2, 3};  // all on a line: zero area
  v = {0, 0, 0, 0};
  c = check_planar_faces(m, u, v);
  CHECK(c.flipped_faces == 0);
  CHECK(c.degenerate_faces == 1);
}

TEST_CASE("perfect parameterization of a triangle disk in space: no flips, boundary on the circle") {
  Mesh m = make_disk(6, 0.3, 11);
  for (int32_t v = 0; v < m.num_vertices(); ++v) m.z[v] = 0.6 * (m.x[v] * m.x[v] - 0.5 * m.y[v] * m.y[v]);
  for (ParamMethod method : {ParamMethod::Perfect, ParamMethod::Uniform, ParamMethod::Cotan}) {
    CAPTURE(param_method_name(method));
    FlipFreeParamOptions o;
    o.method = method;
    o.iteration.max_iterations = 300;  // a curved disk has no length-preserving flattening: no fixed point to reach
    const auto R = flipfree_param(m, o);
    CHECK(R.faces.flipped_faces == count_bad_corners(m, R.uv));
    if (method != ParamMethod::Cotan) {
      CHECK(R.faces.flipped_faces == 0);
      CHECK(R.faces.degenerate_faces == 0);
      CHECK(R.min_weight >= 0.0);
    }
    // Boundary on the unit circle.
    for (const auto& L : boundary_loops(m))
      for (int32_t v : L) CHECK(std::hypot(R.uv[2 * v], R.uv[2 * v + 1]) == doctest::Approx(1.0).epsilon(1e-12));
  }
}

TEST_CASE("perfect parameterization of a quad mesh keeps every face convex") {
  const Mesh m = lifted_quad_grid(8);
  FlipFreeParamOptions o;
  o.iteration.max_iterations = 300;
  const auto R = flipfree_param(m, o);
  CHECK(R.faces.flipped_faces == 0);
  CHECK(count_bad_corners(m, R.uv) == 0);
  CHECK(R.faces.degenerate_faces == 0);
  o.method = ParamMethod::Cotan;
  CHECK_THROWS_AS(flipfree_param(m, o), Error);  // cotan needs triangles
}

TEST_CASE("cotan weights can flip faces where the perfect ones cannot") {
  // A planar Delaunay triangulation, flipped into bad shape, then stretched:
  // many negative cotan weights.
  test::SplitMix rng(5);
  auto T = test::random_disk(60, rng);
  test::flip_random_edges(T, 0.5, rng);
  Mesh m = test::to_mesh(T);
  for (int32_t v = 0; v < m.num_vertices(); ++v) m.z[v] = 0.8 * std::sin(3 * m.x[v]);
  FlipFreeParamOptions o;
  o.method = ParamMethod::Cotan;
  const auto C = flipfree_param(m, o);
  CHECK(C.negative_weights > 0);
  CHECK(C.faces.flipped_faces == count_bad_corners(m, C.uv));
  o.method = ParamMethod::Perfect;
  o.iteration.max_iterations = 300;
  const auto P = flipfree_param(m, o);
  CHECK(P.faces.flipped_faces == 0);
  CHECK(count_bad_corners(m, P.uv) == 0);
  MESSAGE("cotan: " << C.negative_weights << " negative weights, " << C.faces.flipped_faces
                    << " flipped faces; perfect: " << P.iterations << " iterations, 0 flipped");
}

TEST_CASE("parameterization rejects meshes that are not disks") {
  const Mesh closed = make_icosphere(1);
  CHECK_THROWS_AS(flipfree_param(closed), Error);
  // An annulus: a quad grid with the middle face removed.
  Mesh annulus;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) annulus.add_vertex(i, j, 0);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;
      const int32_t a = j * 4 + i;
      const int32_t q[4] = {a, a + 1, a + 5, a + 4};
      annulus.add_face(q);
    }
  CHECK_THROWS_AS(flipfree_param(annulus), Error);
  CHECK_THROWS_AS(parse_param_method("lscm"), Error);
}
