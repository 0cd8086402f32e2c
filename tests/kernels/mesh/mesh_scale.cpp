// Scale invariance of the mesh operators and checks: a
// sphere scaled by 1e-149 or 1e149 (near the ends of the range coordinate_range.hpp
// allows) is the unit sphere to every kernel — the
// same cotangent weights, masses scaled by s^2, gradients by 1/s, and no false
// "zero area" refusal. The oracle is the unit sphere itself: scaling by a power
// of ten is not exact, so the comparisons are relative, at rounding level.
#include <doctest/doctest.h>

#include <cmath>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_gradient.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace {

locus::Mesh scaled(locus::Mesh m, double s) {
  for (auto* c : {&m.x, &m.y, &m.z})
    for (double& v : *c) v *= s;
  return m;
}

double max_rel(locus::ConstView<double> a, locus::ConstView<double> b, double s) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] / s - b[i]) / std::max(std::abs(b[i]), 1e-300));
  return worst;
}

}  // namespace

TEST_CASE("mesh scale: operators and checks of a sphere scaled by 1e-149 and 1e149 equal the unit sphere's") {
  const locus::Mesh unit = locus::make_icosphere(3);
  const locus::CscMatrix L1 = locus::cotan_laplacian(unit);
  const auto M1 = locus::lumped_mass(unit);
  const locus::TriangleGradients G1 = locus::triangle_gradients(unit);
  for (double s : {1e-149, 1e149}) {
    CAPTURE(s);
    const locus::Mesh m = scaled(unit, s);
    const locus::MeshReport r = locus::analyze_mesh(m);
    CHECK(r.degenerate_faces == 0);
    const locus::CscMatrix L = locus::cotan_laplacian(m);
    REQUIRE(L.values.size() == L1.values.size());
    CHECK(max_rel(L.values, L1.values, 1.0) < 1e-12);  // cotangents do not scale
    CHECK(max_rel(locus::lumped_mass(m), M1, s * s) < 1e-12);
    const locus::TriangleGradients G = locus::triangle_gradients(m);
    CHECK(max_rel(G.area, G1.area, s * s) < 1e-12);
    CHECK(max_rel(G.basis, G1.basis, 1.0 / s) < 1e-9);
  }
}
