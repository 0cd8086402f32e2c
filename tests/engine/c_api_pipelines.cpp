// Tests for the C API of the pipelines added by issue 24 (engine/include/locus/locus.h,
// the section after locus_heat_values): each call returns what the C++ Session
// returns for the same arguments (the Session is checked against oracles in
// tests/engine/session_*.cpp), outputs land where locus.h says, and every bad
// argument is a status code naming it: ids out of range (vertices, faces) are
// LOCUS_BAD_USAGE (2), as locus.h promises.
#include "locus/locus.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/session.hpp"

using namespace locus;

namespace {

bool message_has(const char* what) { return std::string(locus_last_error_message()).find(what) != std::string::npos; }

// A C session and the C++ Session of the same mesh.
struct Both {
  Mesh mesh;
  Session cpp;
  locus_session* c = nullptr;
  explicit Both(Mesh m) : mesh(m), cpp(m) {
    std::vector<double> xyz;
    for (int32_t i = 0; i < m.num_vertices(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
    REQUIRE(locus_session_create(xyz.data(), m.num_vertices(), m.face_vertices.data(), m.num_faces(), &c) == LOCUS_OK);
  }
  ~Both() { locus_session_destroy(c); }
  int64_t nv() const { return mesh.num_vertices(); }
};

locus_surface_point at_vertex(int64_t v) { return locus_surface_point{-1, v, {1, 0, 0}}; }
locus_surface_point in_face(int64_t f, double a, double b, double c) { return locus_surface_point{f, -1, {a, b, c}}; }

}  // namespace

TEST_CASE("C API multi-source geodesic: the Session's distances; bad points are LOCUS_BAD_USAGE") {
  Both b(make_icosphere(3));
  const locus_surface_point src[3] = {at_vertex(0), at_vertex(50), in_face(20, 0.1, 0.2, 0.7)};
  std::vector<double> d(b.nv());
  REQUIRE(locus_geodesic_distance_multi(b.c, src, 3, d.data(), nullptr) == LOCUS_OK);
  const std::vector<MeshPoint> pts{MeshPoint::at_vertex(0), MeshPoint::at_vertex(50), MeshPoint::in_face(20, 0.1, 0.2, 0.7)};
  CHECK(d == b.cpp.geodesic_distance(pts));
  locus_run_options o = locus_run_options_default();
  o.t_factor = 2.0;
  REQUIRE(locus_geodesic_distance_multi(b.c, src, 3, d.data(), &o) == LOCUS_OK);
  CHECK(d == b.cpp.geodesic_distance(pts, HeatQuery{2.0}));

  const locus_surface_point bad_face[1] = {in_face(b.mesh.num_faces(), 1, 0, 0)};
  CHECK(locus_geodesic_distance_multi(b.c, bad_face, 1, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("sources[0].face"));
  const locus_surface_point bad_vertex[2] = {at_vertex(0), at_vertex(b.nv())};
  CHECK(locus_geodesic_distance_multi(b.c, bad_vertex, 2, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("sources[1].vertex"));
  const locus_surface_point bad_bary[1] = {in_face(0, 0.5, 0.5, 0.5)};
  CHECK(locus_geodesic_distance_multi(b.c, bad_bary, 1, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(b.c, src, 0, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(b.c, nullptr, 1, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(b.c, src, 3, nullptr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(nullptr, src, 3, d.data(), nullptr) == LOCUS_BAD_USAGE);
}
