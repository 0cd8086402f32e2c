// Tests for mesh views (core/include/locus/mesh_view.hpp, locus_mesh_view in
// locus.h): float positions interleaved at a 32-byte stride
// with uint16 ids give bit-identical results to double/int32 arrays holding
// the same values; unaligned and strided index buffers; every bad argument is
// refused with its status and a message naming it.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/locus.h"
#include "locus/mesh_view.hpp"
#include "locus/session.hpp"

using namespace locus;

namespace {

// A game engine's vertex: position, normal, uv (32 bytes).
struct Vertex {
  float pos[3];
  float normal[3];
  float uv[2];
};
static_assert(sizeof(Vertex) == 32);

struct HostMesh {
  std::vector<Vertex> vertices;
  std::vector<uint16_t> ids16;
  // The same values as doubles and int32 (float -> double is exact).
  std::vector<double> xyz;
  std::vector<int32_t> tris;
};

HostMesh host_mesh() {
  const Mesh m = make_icosphere(3);  // 642 vertices: uint16 ids
  HostMesh h;
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    Vertex v{};
    v.pos[0] = static_cast<float>(m.x[i]);
    v.pos[1] = static_cast<float>(m.y[i]);
    v.pos[2] = static_cast<float>(m.z[i]);
    v.normal[0] = 7.0f;  // junk between the positions: must be skipped
    v.uv[1] = -1.0f;
    h.vertices.push_back(v);
    for (int k = 0; k < 3; ++k) h.xyz.push_back(static_cast<double>(v.pos[k]));
  }
  for (int32_t id : m.face_vertices) {
    h.ids16.push_back(static_cast<uint16_t>(id));
    h.tris.push_back(id);
  }
  return h;
}

locus_mesh_view view_of(const HostMesh& h) {
  locus_mesh_view v;
  std::memset(&v, 0, sizeof v);
  v.positions = h.vertices.data();
  v.position_type = LOCUS_FLOAT32;
  v.position_stride = sizeof(Vertex);
  v.vertex_count = static_cast<int64_t>(h.vertices.size());
  v.indices = h.ids16.data();
  v.index_type = LOCUS_UINT16;
  v.index_stride = 0;  // packed
  v.triangle_count = static_cast<int64_t>(h.ids16.size() / 3);
  return v;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

struct Handle {
  locus_session* s = nullptr;
  ~Handle() { locus_session_destroy(s); }
};

}  // namespace

TEST_CASE("mesh view: float stride-32 positions and uint16 ids give the bits of double/int32 input") {
  const HostMesh h = host_mesh();
  const int64_t nv = static_cast<int64_t>(h.vertices.size()), nf = static_cast<int64_t>(h.tris.size() / 3);
  Handle ref, view;
  REQUIRE(locus_session_create(h.xyz.data(), nv, h.tris.data(), nf, &ref.s) == LOCUS_OK);
  const locus_mesh_view v = view_of(h);
  REQUIRE(locus_session_create_from_view(&v, &view.s) == LOCUS_OK);
  REQUIRE(locus_session_vertex_count(view.s) == nv);
  REQUIRE(locus_session_face_count(view.s) == nf);

  std::vector<double> pa(static_cast<size_t>(3 * nv)), pb(pa.size());
  REQUIRE(locus_session_get_positions(ref.s, pa.data()) == LOCUS_OK);
  REQUIRE(locus_session_get_positions(view.s, pb.data()) == LOCUS_OK);
  CHECK(same_bits(pa, pb));
  CHECK(same_bits(pa, h.xyz));

  for (int64_t src : {int64_t(0), int64_t(17), nv - 1}) {
    std::vector<double> da(static_cast<size_t>(nv)), db(da.size());
    REQUIRE(locus_geodesic_distance(ref.s, src, da.data()) == LOCUS_OK);
    REQUIRE(locus_geodesic_distance(view.s, src, db.data()) == LOCUS_OK);
    CHECK(same_bits(da, db));
    CHECK(da[static_cast<size_t>(src)] == 0.0);
  }
  std::vector<double> ua(static_cast<size_t>(2 * nv)), ub(ua.size());
  REQUIRE(locus_logmap(ref.s, 5, 0.2, ua.data()) == LOCUS_OK);
  REQUIRE(locus_logmap(view.s, 5, 0.2, ub.data()) == LOCUS_OK);
  CHECK(same_bits(ua, ub));  // NaN outside the patch: same bits too

  // The C++ constructor reads the same view.
  MeshView cv;
  cv.positions = h.vertices.data();
  cv.position_type = ScalarType::Float32;
  cv.position_stride = sizeof(Vertex);
  cv.vertex_count = nv;
  cv.indices = h.ids16.data();
  cv.index_type = IndexType::UInt16;
  cv.triangle_count = nf;
  const Session s(cv);
  std::vector<double> dc(static_cast<size_t>(nv)), da(dc.size());
  s.geodesic_distance(17, dc);
  REQUIRE(locus_geodesic_distance(ref.s, 17, da.data()) == LOCUS_OK);
  CHECK(same_bits(dc, da));
}

TEST_CASE("mesh view: unaligned double positions, uint32 ids at a 16-byte triangle stride") {
  const HostMesh h = host_mesh();
  const int64_t nv = static_cast<int64_t>(h.vertices.size()), nf = static_cast<int64_t>(h.tris.size() / 3);
  // Positions packed but one byte off alignment; triangles as {a, b, c, material} uint32.
  std::vector<char> pos(static_cast<size_t>(3 * nv) * sizeof(double) + 1);
  std::memcpy(pos.data() + 1, h.xyz.data(), h.xyz.size() * sizeof(double));
  std::vector<uint32_t> tri4;
  for (int64_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) tri4.push_back(static_cast<uint32_t>(h.tris[3 * f + k]));
    tri4.push_back(0xFFFFFFFFu);  // not an id: must be skipped
  }
  locus_mesh_view v;
  std::memset(&v, 0, sizeof v);
  v.positions = pos.data() + 1;
  v.position_type = LOCUS_FLOAT64;
  v.vertex_count = nv;
  v.indices = tri4.data();
  v.index_type = LOCUS_UINT32;
  v.index_stride = 16;
  v.triangle_count = nf;
  Handle ref, view;
  REQUIRE(locus_session_create(h.xyz.data(), nv, h.tris.data(), nf, &ref.s) == LOCUS_OK);
  REQUIRE(locus_session_create_from_view(&v, &view.s) == LOCUS_OK);
  std::vector<double> da(static_cast<size_t>(nv)), db(da.size());
  REQUIRE(locus_geodesic_distance(ref.s, 3, da.data()) == LOCUS_OK);
  REQUIRE(locus_geodesic_distance(view.s, 3, db.data()) == LOCUS_OK);
  CHECK(same_bits(da, db));
}

TEST_CASE("mesh view: bad views are refused with their status and a message") {
  const HostMesh h = host_mesh();
  locus_session* s = reinterpret_cast<locus_session*>(0x1);
  auto refused = [&](locus_mesh_view v, locus_status want, const char* what) {
    INFO(what);
    const locus_status st = locus_session_create_from_view(&v, &s);
    CHECK(st == want);
    CHECK(s == nullptr);
    CHECK(std::string(locus_last_error_message()).find(what) != std::string::npos);
  };
  const locus_mesh_view good = view_of(h);
  CHECK(locus_session_create_from_view(nullptr, &s) == LOCUS_BAD_USAGE);
  CHECK(locus_session_create_from_view(&good, nullptr) == LOCUS_BAD_USAGE);
  locus_mesh_view v = good;
  v.positions = nullptr;
  refused(v, LOCUS_BAD_USAGE, "positions is NULL");
  v = good;
  v.indices = nullptr;
  refused(v, LOCUS_BAD_USAGE, "indices is NULL");
  v = good;
  v.position_stride = 8;  // shorter than 3 floats
  refused(v, LOCUS_BAD_USAGE, "position_stride");
  v = good;
  v.index_stride = 4;
  refused(v, LOCUS_BAD_USAGE, "index_stride");
  v = good;
  v.position_type = 9;
  refused(v, LOCUS_BAD_USAGE, "position type");
  v = good;
  v.index_type = 0;
  refused(v, LOCUS_BAD_USAGE, "index type");
  v = good;
  v.vertex_count = 0;
  refused(v, LOCUS_BAD_USAGE, "vertex_count");
  v = good;
  v.triangle_count = -1;
  refused(v, LOCUS_BAD_USAGE, "triangle_count");
  v = good;
  v.vertex_count = 100;  // ids above 99 now out of range
  refused(v, LOCUS_BAD_USAGE, "references vertex");

  HostMesh bad = h;
  bad.vertices[40].pos[1] = std::numeric_limits<float>::quiet_NaN();
  v = view_of(bad);
  refused(v, LOCUS_BAD_INPUT, "vertex 40");
  bad = h;
  bad.ids16[1] = bad.ids16[0];  // a zero-area triangle: the cotan operator's checks refuse it
  v = view_of(bad);
  const locus_session_options cotan{LOCUS_OPERATOR_COTAN, 0};
  CHECK(locus_session_create_from_view_ex(&v, &cotan, &s) == LOCUS_BAD_INPUT);  // (the topology check's message)
  CHECK(s == nullptr);
  REQUIRE(locus_session_create_from_view(&v, &s) == LOCUS_OK);  // auto: the robust operator takes it
  CHECK(locus_session_operator(s) == LOCUS_OPERATOR_ROBUST);
  locus_session_destroy(s);
  s = nullptr;
}
