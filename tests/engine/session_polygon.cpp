// locus::Session on polygon meshes (session.hpp "Polygon meshes").
// Oracles: the Euclidean distance on a planar quad grid (multi-source
// polygon heat method); the same Session queries on the ear-clipping
// triangulation given as a triangle mesh (the triangle-only pipelines must run
// on exactly that, bit for bit); the polygon pipelines called directly (the
// Session adds caching only). The CLI's numbers: tests/tools/session_polygon_cli.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/polygon_triangulation.hpp"
#include "locus/pipelines/geodesic/polygon_logmap.hpp"
#include "locus/session.hpp"
#include "tests/engine/session_test_support.hpp"

using namespace locus;

namespace {

// Planar quad grid [0, 1]^2 of n x n squares, with one square split into two triangles (a mixed mesh).
Mesh mixed_grid(int n) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.add_vertex(static_cast<double>(i) / n, static_cast<double>(j) / n, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      if (i == 0 && j == 0) {
        m.add_triangle(a, b, c);
        m.add_triangle(a, c, d);
        continue;
      }
      const int32_t q[4] = {a, b, c, d};
      m.add_face(q);
    }
  return m;
}

std::string error_text(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("session on polygons: vertices kept, triangulation exposed, heat method on the polygons") {
  const Mesh q = make_quad_torus(12, 8);
  REQUIRE_FALSE(q.is_triangle_mesh());
  const Session s(q);
  CHECK(s.has_polygons());
  CHECK(s.num_vertices() == q.num_vertices());
  CHECK(s.num_polygons() == q.num_faces());
  CHECK(s.num_faces() == 2 * q.num_faces());
  const TriangulatedMesh t = triangulate_polygons(q, "");
  CHECK(s.triangle_polygon() == t.face_of);
  CHECK(s.mesh().face_vertices == t.mesh.face_vertices);
  CHECK(s.polygons().face_vertices == q.face_vertices);

  // Geodesic distance and log map: the polygon pipelines, bit for bit, default t_factor 8.
  const PolygonLogMap direct(q);
  CHECK(direct.geodesic().time() == 8.0 * direct.geodesic().mean_edge_length() * direct.geodesic().mean_edge_length());
  std::vector<double> want(q.num_vertices());
  direct.geodesic().query_full(7, want);
  CHECK(s.geodesic_distance(7) == want);
  // One vertex given as a source set: the same numbers (the shift is exactly 0).
  const std::vector<int32_t> one{7};
  CHECK(s.geodesic_distance_from_vertices(ConstView<int32_t>(one)) == want);
  PolygonHeatGeodesicOptions po;
  po.t_factor = 3.0;
  const PolygonHeatGeodesic at3(q, po);
  at3.query_full(7, want);
  CHECK(s.geodesic_distance(7, HeatQuery{3.0, 0.0}) == want);
  CHECK(s.stats().heat_engines == 2);
  const LogMapResult lm = s.logmap(7, 0.25);
  REQUIRE(lm.patch.size() == 24);
  CHECK(lm.patch[0] == 7);
  std::vector<double> d(24), a(24), u(24), v(24);
  direct.query_full(7, lm.patch, {d, a, u, v});
  CHECK(lm.distance == d);
  CHECK(lm.angle == a);
  CHECK(lm.u == u);
  CHECK(lm.v == v);
  CHECK(s.stats().heat_engines == 2);  // the log map reused the t_factor 8 engine

  // The triangle-only pipelines run on the triangulation: the same as a Session on it.
  const Session tri(t.mesh);
  CHECK_FALSE(tri.has_polygons());
  Mesh csr_only = t.mesh;  // triangles in CSR form only (no f0/f1/f2): still a triangle mesh
  csr_only.f0.clear(), csr_only.f1.clear(), csr_only.f2.clear();
  CHECK_FALSE(Session(csr_only).has_polygons());
  const std::vector<int32_t> src{0, 40}, dst{3, 50, 90};
  CHECK(s.heat_values(ConstView<int32_t>(src), ConstView<int32_t>(dst)) ==
        tri.heat_values(ConstView<int32_t>(src), ConstView<int32_t>(dst)));
  const CvtResult c1 = s.cvt(6, 2, 3), c2 = tri.cvt(6, 2, 3);
  CHECK(c1.label == c2.label);
  CHECK(c1.site_xyz == c2.site_xyz);
}

TEST_CASE("session on polygons: multi-source distance on a planar mixed grid is the nearest Euclidean distance") {
  const int n = 16;
  const Mesh m = mixed_grid(n);
  const Session s(m);
  REQUIRE(s.has_polygons());
  const int32_t a = 5 * (n + 1) + 5, b = 11 * (n + 1) + 10;
  // A point in a face: the triangle of mesh() holding it, weights of its corners.
  const Mesh tri = s.mesh();
  const std::vector<MeshPoint> src{MeshPoint::at_vertex(a), MeshPoint::at_vertex(b)};
  const std::vector<double> dist = s.geodesic_distance(ConstView<MeshPoint>(src));
  // Away from the boundary (where the heat method's natural boundary condition bends the distance).
  auto interior = [&](int32_t i) { return std::min({m.x[i], m.y[i], 1 - m.x[i], 1 - m.y[i]}) >= 0.2; };
  double worst = 0;
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    const double da = std::hypot(m.x[i] - m.x[a], m.y[i] - m.y[a]), db = std::hypot(m.x[i] - m.x[b], m.y[i] - m.y[b]);
    if (interior(i)) worst = std::max(worst, std::abs(dist[i] - std::min(da, db)));
  }
  MESSAGE("two sources: max |d - exact| inside " << worst);
  CHECK(worst < 1.0 / n);
  CHECK(std::min(dist[a], dist[b]) == 0.0);
  const int32_t f = 301;  // a triangle of an interior quad
  const std::vector<MeshPoint> in_face{MeshPoint::in_face(f, 0.2, 0.3, 0.5)};
  const std::vector<double> df = s.geodesic_distance(ConstView<MeshPoint>(in_face));
  const auto fv = tri.face(f);
  const double px = 0.2 * tri.x[fv[0]] + 0.3 * tri.x[fv[1]] + 0.5 * tri.x[fv[2]];
  const double py = 0.2 * tri.y[fv[0]] + 0.3 * tri.y[fv[1]] + 0.5 * tri.y[fv[2]];
  worst = 0;
  for (int32_t i = 0; i < m.num_vertices(); ++i)
    if (interior(i)) worst = std::max(worst, std::abs(df[i] - std::hypot(m.x[i] - px, m.y[i] - py)));
  MESSAGE("point in a face: max |d - exact| inside " << worst);
  CHECK(worst < 1.0 / n);
}

TEST_CASE("session on polygons: bad polygons are refused naming the face; set_positions keeps them simple") {
  Mesh bowtie = make_quad_torus(6, 4);
  // Face 5's corners 1 and 2 swapped: its boundary crosses itself.
  std::swap(bowtie.face_vertices[bowtie.face_offsets[5] + 1], bowtie.face_vertices[bowtie.face_offsets[5] + 2]);
  bowtie.source = "bowtie";
  CHECK(test::code_of([&] { Session s(bowtie); }) == ErrorCode::BadInput);
  CHECK(error_text([&] { Session s(bowtie); }).find("face 5") != std::string::npos);

  Mesh flat = mixed_grid(4);
  const int32_t f = flat.num_faces() - 1;  // the last quad on four vertices of the bottom row: no area
  for (int32_t k = 0; k < 4; ++k) flat.face_vertices[flat.face_offsets[f] + k] = k;
  CHECK(error_text([&] { Session s(flat); }).find("face " + std::to_string(f)) != std::string::npos);

  Mesh bad_id = mixed_grid(4);
  bad_id.face_vertices.back() = 1000;
  CHECK(test::code_of([&] { Session s(bad_id); }) == ErrorCode::BadInput);

  // Moving a quad's corner across the opposite edge makes it a bow-tie: refused, old positions kept.
  const Mesh g = mixed_grid(4);
  Session s(g);
  const std::vector<double> before = s.geodesic_distance(0);
  std::vector<double> xyz;
  for (int32_t i = 0; i < g.num_vertices(); ++i) xyz.insert(xyz.end(), {g.x[i], g.y[i], g.z[i]});
  const auto q = g.face(7);
  xyz[3 * q[2] + 1] -= 0.5;  // corner 2 of quad 7 moves one row down, past corner 1
  const std::string msg = error_text([&] { s.set_positions(ConstView<double>(xyz)); });
  CHECK(msg.find("face 7") != std::string::npos);
  CHECK(s.geodesic_distance(0) == before);
  CHECK(s.stats().positions_version == 0);
  // A valid move reaches the polygon operators: the answers of a new Session on the moved mesh.
  xyz[3 * q[2] + 1] += 0.5;
  for (size_t k = 2; k < xyz.size(); k += 3) xyz[k] = 0.1 * xyz[k - 2] * xyz[k - 1];  // a bent sheet
  s.set_positions(ConstView<double>(xyz));
  Mesh moved = g;
  for (int32_t i = 0; i < g.num_vertices(); ++i) moved.z[i] = xyz[3 * i + 2];
  const Session fresh(moved);
  CHECK(s.geodesic_distance(0) == fresh.geodesic_distance(0));
  CHECK(s.logmap(6, 0.5).u == fresh.logmap(6, 0.5).u);
  CHECK(s.polygons().z == moved.z);
}

TEST_CASE("session on polygons: concurrent first queries build the polygon engine once, same answers") {
  const Mesh q = make_quad_torus(10, 6);
  const Session s(q);
  const std::vector<double> want = Session(q).geodesic_distance(3);
  std::vector<std::vector<double>> got(4);
  std::vector<LogMapResult> maps(4);
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k)
    threads.emplace_back([&, k] {
      got[k] = s.geodesic_distance(3);
      maps[k] = s.logmap(3, 0.3);
    });
  for (auto& t : threads) t.join();
  for (int k = 0; k < 4; ++k) {
    CHECK(got[k] == want);
    CHECK(maps[k].u == maps[0].u);
  }
  CHECK(s.stats().heat_engines == 1);
}
