// Numerical faults through the C API: a mesh with two
// components (geodesic distance NaN, no value, in the other component, with
// locus_valid_mask's 0 there; log map
// confined to the center's component, zero heat across), huge and tiny
// diffusion times (LOCUS_NUMERICAL with a message, or finite values), and
// collapsed or needle triangles. Argument checking (NULL, counts, ids) is in
// tests/engine/c_api.cpp; fuzz_c_api attacks the same entry points.
#include "locus/locus.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"

using namespace locus;

namespace {

struct Arrays {
  std::vector<double> xyz;
  std::vector<int32_t> tris;
};

// Two icospheres of level 2, the second shifted by 3 along x.
Arrays two_spheres(int32_t& per_copy) {
  const Mesh m = make_icosphere(2);
  per_copy = m.num_vertices();
  Arrays a;
  for (int copy = 0; copy < 2; ++copy) {
    for (int32_t i = 0; i < m.num_vertices(); ++i) a.xyz.insert(a.xyz.end(), {m.x[i] + 3.0 * copy, m.y[i], m.z[i]});
    for (int32_t v : m.face_vertices) a.tris.push_back(v + copy * per_copy);
  }
  return a;
}

}  // namespace

TEST_CASE("C API faults: two components") {
  int32_t na = 0;
  const Arrays a = two_spheres(na);
  const int64_t nv = static_cast<int64_t>(a.xyz.size() / 3), nf = static_cast<int64_t>(a.tris.size() / 3);
  locus_session* s = nullptr;
  REQUIRE(locus_session_create(a.xyz.data(), nv, a.tris.data(), nf, &s) == LOCUS_OK);

  // Geodesic distance: finite in the source's component, NaN (no value, no
  // path) in the other, as the CLI writes it; the mask says which is which.
  std::vector<double> d(nv);
  std::vector<int32_t> valid(nv, -1);
  REQUIRE(locus_geodesic_distance(s, 3, d.data()) == LOCUS_OK);
  CHECK(locus_valid_mask(d.data(), nv, 1, valid.data()) == na);
  for (int64_t v = 0; v < nv; ++v) {
    INFO("vertex " << v);
    if (v < na) CHECK(std::isfinite(d[v]));
    else CHECK(std::isnan(d[v]));
    CHECK(valid[v] == (v < na ? 1 : 0));
  }
  CHECK(d[3] == 0.0);
  // From a point in a face of the first copy: the same convention.
  const locus_surface_point p{0, -1, {0.2, 0.3, 0.5}};
  REQUIRE(locus_geodesic_distance_multi(s, &p, 1, d.data(), nullptr) == LOCUS_OK);
  for (int64_t v = 0; v < nv; ++v) CHECK((v < na ? std::isfinite(d[v]) : std::isnan(d[v])));
  CHECK(locus_valid_mask(nullptr, nv, 1, valid.data()) == -1);
  CHECK(std::string(locus_last_error_message()).find("values is NULL") != std::string::npos);

  // Log map of the whole mesh around a vertex of the second copy: the disk stops
  // at its component (finite there), NaN elsewhere (documented: outside the disk).
  std::vector<double> uv(2 * nv);
  REQUIRE(locus_logmap(s, na + 1, 1.0, uv.data()) == LOCUS_OK);
  CHECK(locus_valid_mask(uv.data(), nv, 2, valid.data()) == nv - na);
  for (int64_t v = 0; v < nv; ++v) {
    INFO("vertex " << v);
    if (v >= na) CHECK(std::isfinite(uv[2 * v]));
    else CHECK(std::isnan(uv[2 * v]));
    CHECK(valid[v] == (v >= na ? 1 : 0));
  }

  // Heat never crosses components.
  const int64_t src[2] = {0, na}, tgt[2] = {1, na + 1};
  double h[4];
  REQUIRE(locus_heat_values(s, src, 2, tgt, 2, h, nullptr) == LOCUS_OK);
  CHECK(h[0] > 0.0);
  CHECK(h[1] == 0.0);
  CHECK(h[2] == 0.0);
  CHECK(h[3] > 0.0);
  CHECK(h[0] == doctest::Approx(h[3]).epsilon(1e-12));  // the copies are congruent
  locus_session_destroy(s);
}

TEST_CASE("C API faults: huge and tiny diffusion times") {
  const Mesh m = make_icosphere(2);
  std::vector<double> xyz;
  for (int32_t i = 0; i < m.num_vertices(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
  locus_session* s = nullptr;
  REQUIRE(locus_session_create(xyz.data(), m.num_vertices(), m.face_vertices.data(), m.num_faces(), &s) == LOCUS_OK);
  std::vector<double> d(m.num_vertices());
  for (double tf : {1e300, 1e200, 1e-300}) {
    locus_run_options o = locus_run_options_default();
    o.t_factor = tf;
    const locus_status st = locus_geodesic_distance_ex(s, 0, d.data(), &o);
    INFO("t_factor " << tf << ": status " << st << ", " << locus_last_error_message());
    if (tf > 1e6) {  // beyond the heat method's longest time (1e6 h^2): refused naming the limit
      CHECK(st == LOCUS_BAD_USAGE);
      CHECK(std::string(locus_last_error_message()).find("at most 1e+06") != std::string::npos);
      continue;
    }
    CHECK((st == LOCUS_OK || st == LOCUS_NUMERICAL));
    if (st == LOCUS_OK) {
      for (double x : d) CHECK(std::isfinite(x));
    } else {
      CHECK(std::strlen(locus_last_error_message()) > 0);
    }
  }
  for (double tf : {0.0 - 1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    locus_run_options o = locus_run_options_default();
    o.t_factor = tf;
    INFO("t_factor " << tf);
    CHECK(locus_geodesic_distance_ex(s, 0, d.data(), &o) == LOCUS_BAD_USAGE);
    CHECK(std::string(locus_last_error_message()).find("t_factor") != std::string::npos);
  }
  locus_session_destroy(s);
}

TEST_CASE("C API faults: collapsed and needle triangles") {
  // A 5x5 planar grid; vertex 1 on the diagonal of face (0, 1, 6) makes it flat.
  std::vector<double> xyz;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) xyz.insert(xyz.end(), {i / 4.0, j / 4.0, 0.0});
  std::vector<int32_t> tris;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = j * 5 + i;
      tris.insert(tris.end(), {a, a + 1, a + 6, a, a + 6, a + 5});
    }
  for (double lift : {0.0, 1e-9}) {
    xyz[3] = 0.125;
    xyz[4] = 0.125 + lift;
    locus_session* s = nullptr;
    // The cotan operator's refusals (auto would take both meshes on the robust operator).
    const locus_session_options cotan{LOCUS_OPERATOR_COTAN, 0};
    const locus_status st = locus_session_create_ex(xyz.data(), 25, tris.data(), 32, &cotan, &s);
    INFO("lift " << lift << ": " << locus_last_error_message());
    if (lift == 0.0) {
      CHECK(st == LOCUS_BAD_INPUT);
      CHECK(std::string(locus_last_error_message()).find("face 0") != std::string::npos);
      CHECK(s == nullptr);
      continue;
    }
    REQUIRE(st == LOCUS_OK);
    std::vector<double> d(25);
    // An angle of ~1e-9 rad: refused by name (pipelines/src/geodesic/heat_geodesic.cpp, needles).
    const locus_status g = locus_geodesic_distance(s, 12, d.data());
    CHECK(g == LOCUS_BAD_INPUT);
    CHECK(std::string(locus_last_error_message()).find("needle") != std::string::npos);
    locus_session_destroy(s);
  }
}
