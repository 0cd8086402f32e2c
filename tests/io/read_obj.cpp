// Tests for io/src/read_obj.cpp: every corner syntax, relative indices, ignored
// statements, and exact coordinates against values written by hand.
#include <doctest/doctest.h>

#include <vector>

#include "io_test_support.hpp"
#include "locus/mesh_io.hpp"

using locus_test::parse;
using locus_test::parse_error;

namespace {
std::vector<int32_t> face_of(const locus::Mesh& m, int32_t f) {
  const auto s = m.face(f);
  return {s.begin(), s.end()};
}
}  // namespace

TEST_CASE("obj: triangle with exact coordinates, triangle fast path") {
  const auto m = parse("v 0.5 -1.25 3e2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "obj");
  REQUIRE(m.num_vertices() == 3);
  REQUIRE(m.num_faces() == 1);
  CHECK(m.x[0] == 0.5);
  CHECK(m.y[0] == -1.25);
  CHECK(m.z[0] == 300.0);
  CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2});
  CHECK(m.is_triangle_mesh());
  CHECK(m.f0 == std::vector<int32_t>{0});
  CHECK(m.f2 == std::vector<int32_t>{2});
  CHECK(m.source == "t.obj");
}

TEST_CASE("obj: corner forms v, v/vt, v//vn, v/vt/vn and polygon faces") {
  const char* text =
      "# a comment\n"
      "mtllib x.mtl\no obj\ng grp\ns 1\nusemtl red\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 2\n"
      "vt 0 0\nvt 1 0\nvn 0 0 1\n"
      "\n"
      "f 1/1 2/2 3/1\n"
      "f 1//1 3//1 4//1\n"
      "f 1/1/1 2/2/1 3/1/1 4/2/1\n"
      "f 1 2 3 4 5\n"
      "l 1 2\np 3\n";
  const auto m = parse(text, "obj");
  REQUIRE(m.num_vertices() == 5);
  REQUIRE(m.num_faces() == 4);
  CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2});
  CHECK(face_of(m, 1) == std::vector<int32_t>{0, 2, 3});
  CHECK(face_of(m, 2) == std::vector<int32_t>{0, 1, 2, 3});
  CHECK(face_of(m, 3) == std::vector<int32_t>{0, 1, 2, 3, 4});
  CHECK_FALSE(m.is_triangle_mesh());
  CHECK(m.f0.empty());
}

TEST_CASE("obj: negative indices are relative to the vertices read so far") {
  // After 3 vertices, -1 is vertex 3 (1-based) = id 2; after 4, -1 is id 3.
  const auto m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n", "obj");
  REQUIRE(m.num_faces() == 2);
  CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2});
  CHECK(face_of(m, 1) == std::vector<int32_t>{1, 3, 2});
}

TEST_CASE("obj: w coordinate, trailing colour, inline comments, CRLF, leading +") {
  const auto m = parse("v 1 2 3 1.0\r\nv +4 5 6 0.1 0.2 0.3\r\nv 7 8 9 # c\r\nf 1 2 3 # tri\r\n", "obj");
  REQUIRE(m.num_vertices() == 3);
  CHECK(m.x[1] == 4.0);
  CHECK(m.z[2] == 9.0);
  CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2});
}

TEST_CASE("obj: faces may name vertices defined later in the file") {
  const auto m = parse("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "obj");
  CHECK(m.num_vertices() == 3);
  CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2});
}

TEST_CASE("obj: a vertex-only file is a point set with no faces") {
  const auto m = parse("v 0 0 0\nv 1 1 1\n", "obj");
  CHECK(m.num_vertices() == 2);
  CHECK(m.num_faces() == 0);
}

TEST_CASE("obj: degenerate, non-manifold, unreferenced, disconnected geometry is not a reader error") {
  // Zero-area (collinear) triangle plus an unreferenced vertex: accepted.
  const auto m = parse("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 5 5 5\nf 1 2 3\n", "obj");
  CHECK(m.num_faces() == 1);
  CHECK(m.num_vertices() == 4);
  // Three triangles on edge (1,2) (non-manifold) and a second component.
  const auto n = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                       "v 9 9 9\nv 10 9 9\nv 9 10 9\n"
                       "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 6 7 8\n",
                       "obj");
  CHECK(n.num_faces() == 4);
  CHECK(face_of(n, 3) == std::vector<int32_t>{5, 6, 7});
}

TEST_CASE("obj: malformed statements name the line") {
  auto e = parse_error("v 0 0 0\nv 1 0\nv 0 1 0\n", "obj");
  CHECK(e.thrown);
  CHECK(e.code == locus::ErrorCode::BadInput);
  CHECK(e.has("t.obj:2:"));
  CHECK(e.has("coordinates"));
  e = parse_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x3\n", "obj");
  CHECK(e.has("t.obj:4:"));
  CHECK(e.has("malformed corner"));
  e = parse_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/a\n", "obj");
  CHECK(e.has("malformed corner"));
  e = parse_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "obj");
  CHECK(e.has("index 0"));
  e = parse_error("v 0 0 zero\n", "obj");
  CHECK(e.has("expected a number"));
  CHECK(e.has("'zero'"));
}
