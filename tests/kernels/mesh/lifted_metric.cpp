// Tests for kernels/mesh/lifted_metric.{hpp,cpp}. Oracles: the cotan heat
// operator and lumped mass of kernels/mesh/mesh_operators (cross products, not
// edge lengths) for R^3 positions; triangles of known area (3-4-5, equilateral,
// an isosceles needle); cross-product areas for
// face_areas; scaling laws of the lift.
#include "locus/kernels/mesh/lifted_metric.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

using namespace locus;

TEST_CASE("triangle area from squared lengths: known triangles, needles, impossible lengths") {
  CHECK(triangle_area_from_squared_lengths(9, 16, 25) == doctest::Approx(6.0).epsilon(1e-15));
  CHECK(triangle_area_from_squared_lengths(25, 9, 16) == doctest::Approx(6.0).epsilon(1e-15));
  CHECK(triangle_area_from_squared_lengths(1, 1, 1) == doctest::Approx(std::sqrt(3.0) / 4).epsilon(1e-15));
  // Isosceles needle: base 2e-8, legs 1: height sqrt(1 - 1e-16), area 1e-8 (to 1e-16).
  const double b = 2e-8;
  CHECK(triangle_area_from_squared_lengths(b * b, 1.0, 1.0) == doctest::Approx(1e-8).epsilon(1e-12));
  CHECK(triangle_area_from_squared_lengths(1, 1, 4) == 0.0);   // degenerate: 1 + 1 = 2
  CHECK(triangle_area_from_squared_lengths(1, 1, 9) == 0.0);   // violates the triangle inequality
}

TEST_CASE("face areas from positions: the cross-product areas in R^3, the same in R^6 with zero padding") {
  const Mesh m = make_random_sphere(200, 4);
  const HostVector<double> a = face_areas(m);
  REQUIRE(a.size() == static_cast<size_t>(m.num_faces()));
  std::vector<double> p6(6 * static_cast<size_t>(m.num_vertices()), 0.0);
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    p6[6 * v + 1] = m.x[v];  // coordinates spread over other axes of R^6
    p6[6 * v + 3] = m.y[v];
    p6[6 * v + 5] = m.z[v];
  }
  const HostVector<double> a6 = face_areas_from_positions(m, p6, 6);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t i = m.f0[f], j = m.f1[f], k = m.f2[f];
    const double u[3] = {m.x[j] - m.x[i], m.y[j] - m.y[i], m.z[j] - m.z[i]};
    const double w[3] = {m.x[k] - m.x[i], m.y[k] - m.y[i], m.z[k] - m.z[i]};
    const double c[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double want = 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    CHECK(a[f] == doctest::Approx(want).epsilon(1e-12));
    CHECK(a6[f] == doctest::Approx(want).epsilon(1e-12));
  }
  CHECK_THROWS_AS(face_areas_from_positions(m, p6, 5), Error);
  CHECK_THROWS_AS(face_areas_from_positions(make_quad_torus(4, 4), std::vector<double>(48), 3), Error);
}

TEST_CASE("lifted metric: heat operator from edge lengths equals the cotan heat operator; lifted at lambda 0 it is scaled") {
  const Mesh m = make_random_sphere(300, 8);
  const int32_t n = m.num_vertices();
  std::vector<double> p3(3 * static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) {
    p3[3 * v] = m.x[v];
    p3[3 * v + 1] = m.y[v];
    p3[3 * v + 2] = m.z[v];
  }
  HostVector<double> mass;
  double h = 0;
  const double t = 0.01;
  const CscMatrix A = heat_operator_from_positions(m, p3, 3, t, mass, h);
  const CscMatrix B = heat_operator(m, t);
  const auto mref = lumped_mass(m);
  REQUIRE(A.colptr == B.colptr);
  REQUIRE(A.rowind == B.rowind);
  for (size_t k = 0; k < A.values.size(); ++k) CHECK(A.values[k] == doctest::Approx(B.values[k]).epsilon(1e-10));
  for (int32_t v = 0; v < n; ++v) CHECK(mass[v] == doctest::Approx(mref[v]).epsilon(1e-12));
  CHECK(h == doctest::Approx(mean_edge_length(m)).epsilon(1e-12));
  // Lift with lambda = 0: positions scaled by 1/2 (the sphere's bounding box side is ~2).
  const std::vector<double> lifted = lifted_positions(m, 0.0);
  HostVector<double> mass6;
  double h6 = 0;
  heat_operator_from_positions(m, lifted, 6, t, mass6, h6);
  double side = 0;
  for (const auto* c : {&m.x, &m.y, &m.z})
    side = std::max(side, *std::max_element(c->begin(), c->end()) - *std::min_element(c->begin(), c->end()));
  CHECK(h6 == doctest::Approx(h / side).epsilon(1e-12));
  for (int32_t v = 0; v < n; ++v) CHECK(mass6[v] == doctest::Approx(mref[v] / (side * side)).epsilon(1e-12));
}

TEST_CASE("lifted metric: the lift's normal part scales with lambda; zero-area and shapeless input refused") {
  const Mesh m = make_icosphere(1);
  const std::vector<double> a = lifted_positions(m, 0.0), b = lifted_positions(m, 0.5);
  const HostVector<double> nrm = area_weighted_normals(m);
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    for (int c = 0; c < 3; ++c) {
      CHECK(a[6 * v + c] == b[6 * v + c]);
      CHECK(a[6 * v + 3 + c] == 0.0);
      CHECK(b[6 * v + 3 + c] == doctest::Approx(0.5 * nrm[3 * v + c]).epsilon(1e-15));
      CHECK(a[6 * v + c] >= 0.0);
      CHECK(a[6 * v + c] <= 1.0);
    }
  Mesh flat;  // every vertex at one point: no extent, every face of zero area
  for (int k = 0; k < 3; ++k) {
    flat.x.push_back(1.0);
    flat.y.push_back(1.0);
    flat.z.push_back(1.0);
  }
  flat.add_triangle(0, 1, 2);
  CHECK_THROWS_AS(lifted_positions(flat, 0.1), Error);
  HostVector<double> mass;
  double h = 0;
  CHECK_THROWS_AS(heat_operator_from_positions(flat, std::vector<double>(9, 1.0), 3, 0.1, mass, h), Error);
  CHECK_THROWS_AS(heat_operator_from_positions(flat, std::vector<double>(8, 1.0), 3, 0.1, mass, h), Error);
}
