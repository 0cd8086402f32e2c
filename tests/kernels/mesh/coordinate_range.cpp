// The sizes of mesh the operators accept (kernels/include/locus/kernels/mesh/coordinate_range.hpp):
// beyond them areas and squared lengths overflow or underflow, and the refusal
// names that cause and the range instead of a symptom ("face 0 has zero area",
// "mesh has no area"). Oracle: the diagonal of the unit icosphere's bounding box,
// computed here directly, times the scale.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/coordinate_range.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace {

locus::Mesh scaled(locus::Mesh m, double s) {
  for (auto* c : {&m.x, &m.y, &m.z})
    for (double& v : *c) v *= s;
  return m;
}

double unit_diagonal(const locus::Mesh& m) {
  double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double p[3] = {m.x[v], m.y[v], m.z[v]};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const locus::Error& e) {
    CHECK(e.code() == locus::ErrorCode::BadInput);
    return e.what();
  }
  FAIL("no error");
  return {};
}

}  // namespace

TEST_CASE("coordinate range: the bounding-box diagonal at any scale, without overflow or underflow") {
  const locus::Mesh unit = locus::make_icosphere(2);
  const double d = unit_diagonal(unit);
  for (double s : {1.0, 1e-300, 1e-160, 1e160, 1e300}) {
    CAPTURE(s);
    CHECK(locus::bounding_box_diagonal(scaled(unit, s)) / s == doctest::Approx(d).epsilon(1e-14));
  }
  const double lo[3] = {-1.7e308, 0, 0}, hi[3] = {1.7e308, 0, 0};
  CHECK(locus::bounding_box_diagonal(lo, hi) == INFINITY);
  CHECK(locus::bounding_box_diagonal(locus::Mesh{}) == 0.0);
}

TEST_CASE("coordinate range: sizes beyond it are refused naming overflow or underflow and the range") {
  const locus::Mesh unit = locus::make_icosphere(2);
  locus::MeshRequirements req;
  for (double s : {1e155, 1e160, 1e300, 1e-155, 1e-170, 1e-300}) {
    CAPTURE(s);
    const locus::Mesh m = scaled(unit, s);
    for (const std::string& msg :
         {message_of([&] { locus::check_mesh_size(m); }), message_of([&] { locus::check_requirements(m, req); }),
          message_of([&] { locus::cotan_laplacian(m); }), message_of([&] { locus::heat_operator(m, 1.0); }),
          message_of([&] { locus::regularized_laplacian(m, 1e-6); })}) {
      CAPTURE(msg);
      CHECK(msg.find(s > 1 ? "overflow" : "underflow") != std::string::npos);
      CHECK(msg.find("between 1e-150 and 1e+150") != std::string::npos);
      CHECK(msg.find("zero area") == std::string::npos);
    }
  }
  // Inside the range, and a mesh whose vertices coincide (left to the degenerate-face check).
  CHECK_NOTHROW(locus::check_mesh_size(scaled(unit, 1e149)));
  CHECK_NOTHROW(locus::check_mesh_size(scaled(unit, 1e-149)));
  CHECK_NOTHROW(locus::check_mesh_size(scaled(unit, 0.0)));
}
