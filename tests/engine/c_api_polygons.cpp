// The C API's polygon constructors (locus.h: locus_session_create_polygons,
// locus_session_create_from_polygon_view): the same numbers as the C++ Session
// on the same polygon mesh (itself checked against the polygon pipelines and the
// plane's distances in tests/engine/session_polygon.cpp; against the CLI in
// tests/tools/session_polygon_cli.cpp), float/uint16 views bit-identical to
// double/int32 arrays, and bad faces refused naming the face.
#include "locus/locus.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/session.hpp"

using namespace locus;

namespace {

bool message_has(const char* what) { return std::string(locus_last_error_message()).find(what) != std::string::npos; }

struct Guard {
  locus_session* s = nullptr;
  ~Guard() { locus_session_destroy(s); }
};

// Equal, NaN (no value) where the other has NaN.
bool same(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
  return true;
}

}  // namespace

TEST_CASE("c api: polygon sessions equal the C++ Session; views; bad faces named") {
  // Vertex coordinates exact in float, so a float view reads the same values.
  Mesh q = make_quad_torus(10, 6);
  for (auto* c : {&q.x, &q.y, &q.z})
    for (double& x : *c) x = static_cast<float>(x);
  const int64_t nv = q.num_vertices(), nf = q.num_faces();
  std::vector<double> xyz;
  std::vector<float> xyzf;
  for (int32_t i = 0; i < nv; ++i) {
    xyz.insert(xyz.end(), {q.x[i], q.y[i], q.z[i]});
    xyzf.insert(xyzf.end(), {float(q.x[i]), float(q.y[i]), float(q.z[i])});
  }
  const Session ref(q);
  Guard a;
  REQUIRE(locus_session_create_polygons(xyz.data(), nv, q.face_offsets.data(), q.face_vertices.data(), nf, &a.s) ==
          LOCUS_OK);
  CHECK(locus_session_vertex_count(a.s) == nv);
  CHECK(locus_session_face_count(a.s) == 2 * nf);  // the triangulation's

  std::vector<double> d(nv), uv(2 * nv);
  REQUIRE(locus_geodesic_distance(a.s, 4, d.data()) == LOCUS_OK);
  CHECK(same(d, ref.geodesic_distance(4)));  // the polygon heat method, t_factor 8
  REQUIRE(locus_logmap(a.s, 4, 0.2, uv.data()) == LOCUS_OK);
  const LogMapResult lm = ref.logmap(4, 0.2);
  std::vector<double> want(2 * nv, std::nan(""));
  for (size_t p = 0; p < lm.patch.size(); ++p) want[2 * lm.patch[p]] = lm.u[p], want[2 * lm.patch[p] + 1] = lm.v[p];
  CHECK(same(uv, want));
  std::vector<int32_t> labels(nv);
  REQUIRE(locus_cvt(a.s, 5, 2, 7, labels.data()) == LOCUS_OK);
  CHECK(labels == ref.cvt(5, 2, 7).label);

  // Chapter 2 on the quads themselves: their edges (a quad torus: 2 per quad), no diagonals.
  const int64_t ne = locus_session_edge_count(a.s);
  CHECK(ne == 2 * nf);
  std::vector<int32_t> edges(2 * ne);
  std::vector<double> weights(ne);
  REQUIRE(locus_perfect_laplacian(a.s, 0, 3, 1e-6, edges.data(), weights.data(), nullptr, nullptr, nullptr) == LOCUS_OK);
  const PerfectLaplacianOutput pl = perfect_laplacian_of(q, {false, 3, 1e-6, true});
  CHECK(edges == pl.edges);
  CHECK(weights == pl.weights);

  // The same mesh as float positions at a 16-byte stride and uint16 ids.
  std::vector<float> padded;
  for (int64_t i = 0; i < nv; ++i) padded.insert(padded.end(), {xyzf[3 * i], xyzf[3 * i + 1], xyzf[3 * i + 2], -1.0f});
  std::vector<uint16_t> off16(q.face_offsets.begin(), q.face_offsets.end()),
      ids16(q.face_vertices.begin(), q.face_vertices.end());
  locus_polygon_view view = {padded.data(), LOCUS_FLOAT32, 16, nv, off16.data(), ids16.data(), LOCUS_UINT16, nf};
  Guard b;
  REQUIRE(locus_session_create_from_polygon_view(&view, &b.s) == LOCUS_OK);
  std::vector<double> d2(nv);
  REQUIRE(locus_geodesic_distance(b.s, 4, d2.data()) == LOCUS_OK);
  CHECK(same(d, d2));

  // Bad input: a face of 2 corners, a bow-tie, offsets not from 0, an id out of range.
  Guard bad;
  std::vector<int32_t> off(q.face_offsets), ids(q.face_vertices);
  std::vector<int32_t> short_off = off;
  short_off[3] = short_off[2] + 2;
  CHECK(locus_session_create_polygons(xyz.data(), nv, short_off.data(), ids.data(), nf, &bad.s) == LOCUS_BAD_INPUT);
  CHECK(message_has("face 2 has 2 corners"));
  CHECK(bad.s == nullptr);
  std::vector<int32_t> crossed = ids;
  std::swap(crossed[off[6] + 1], crossed[off[6] + 2]);
  CHECK(locus_session_create_polygons(xyz.data(), nv, off.data(), crossed.data(), nf, &bad.s) == LOCUS_BAD_INPUT);
  CHECK(message_has("face 6"));
  std::vector<int32_t> shifted = off;
  shifted[0] = 1;
  CHECK(locus_session_create_polygons(xyz.data(), nv, shifted.data(), ids.data(), nf, &bad.s) == LOCUS_BAD_USAGE);
  std::vector<int32_t> far = ids;
  far[off[3]] = static_cast<int32_t>(nv);
  CHECK(locus_session_create_polygons(xyz.data(), nv, off.data(), far.data(), nf, &bad.s) == LOCUS_BAD_USAGE);
  CHECK(message_has("face 3 references vertex"));
  CHECK(locus_session_create_polygons(xyz.data(), nv, nullptr, ids.data(), nf, &bad.s) == LOCUS_BAD_USAGE);
  CHECK(locus_session_create_polygons(xyz.data(), nv, off.data(), ids.data(), 0, &bad.s) == LOCUS_BAD_USAGE);
  CHECK(bad.s == nullptr);
}
