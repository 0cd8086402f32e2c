// Tests for io/src/read_ply.cpp: ascii and both binary byte orders, any scalar
// type and property order, both face list names, skipped unknown elements and
// list properties. Binary fixtures are assembled here byte by byte
// (locus_test::put), independently of locus's writer.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "io_test_support.hpp"
#include "locus/mesh_io.hpp"

using locus_test::parse;
using locus_test::parse_error;
using locus_test::put;

namespace {

std::vector<int32_t> face_of(const locus::Mesh& m, int32_t f) {
  const auto s = m.face(f);
  return {s.begin(), s.end()};
}

// The reference square: 4 vertices, 2 triangles; coordinates chosen exactly
// representable in float and in the small integer types.
const double kX[4] = {0, 1, 1, 0}, kY[4] = {0, 0, 2, 2}, kZ[4] = {-1, 3, 5, 7};
const int kF[2][3] = {{0, 1, 2}, {0, 2, 3}};

void check_square(const locus::Mesh& m) {
  REQUIRE(m.num_vertices() == 4);
  REQUIRE(m.num_faces() == 2);
  for (int v = 0; v < 4; ++v) {
    CHECK(m.x[v] == kX[v]);
    CHECK(m.y[v] == kY[v]);
    CHECK(m.z[v] == kZ[v]);
  }
  CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2});
  CHECK(face_of(m, 1) == std::vector<int32_t>{0, 2, 3});
  CHECK(m.is_triangle_mesh());
}

}  // namespace

TEST_CASE("ply ascii: square with comments, obj_info and CRLF") {
  std::string t =
      "ply\r\nformat ascii 1.0\r\ncomment hello\r\nobj_info made by hand\r\n"
      "element vertex 4\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
      "element face 2\r\nproperty list uchar int vertex_indices\r\nend_header\r\n";
  for (int v = 0; v < 4; ++v) t += std::to_string(kX[v]) + " " + std::to_string(kY[v]) + " " + std::to_string(kZ[v]) + "\r\n";
  t += "3 0 1 2\r\n3 0 2 3\r\n";
  check_square(parse(t, "ply"));
}

TEST_CASE("ply ascii: values may wrap across lines; unknown elements and lists are skipped") {
  const char* t =
      "ply\nformat ascii 1.0\n"
      "element vertex 4\nproperty uchar red\nproperty list uchar float junk\nproperty double z\n"
      "property double y\nproperty double x\n"
      "element edge 2\nproperty int a\nproperty int b\n"
      "element face 2\nproperty list uint8 uint32 vertex_index\nproperty list uchar float texcoord\n"
      "end_header\n"
      "9 2 0.5 0.25 -1 0 0\n"
      "9 0 3 0 1\n"
      "9 1 7 5 2 1\n"
      "9 0 7\n2 0\n"
      "0 1\n2 3\n"
      "3 0 1 2 0\n"
      "3 0 2 3 2 0.5 0.5\n";
  check_square(parse(t, "ply"));
}

TEST_CASE("ply binary: both byte orders, several scalar types and property orders") {
  for (const bool big : {false, true}) {
    CAPTURE(big);
    // Layout 1: float x y z, uchar count, int indices (the common layout).
    {
      std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
      for (int v = 0; v < 4; ++v) { put(s, float(kX[v]), big); put(s, float(kY[v]), big); put(s, float(kZ[v]), big); }
      for (const auto& f : kF) { put(s, uint8_t(3), big); for (int i : f) put(s, int32_t(i), big); }
      check_square(parse(s, "ply"));
    }
    // Layout 2: extra properties before/between, z y x order, int16/double/int8
    // coordinates, ushort count and uint16 indices, an unknown list in faces.
    {
      std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\ncomment mixed\nelement vertex 4\nproperty uint8 red\nproperty int16 z\n"
                      "property list int short junk\nproperty float64 y\nproperty char x\nproperty float nx\n"
                      "element material 1\nproperty list uchar double coeffs\n"
                      "element face 2\nproperty int id\nproperty list ushort uint16 vertex_index\n"
                      "property list uchar float texcoord\nend_header\n";
      for (int v = 0; v < 4; ++v) {
        put(s, uint8_t(200), big);
        put(s, int16_t(kZ[v]), big);
        put(s, int32_t(v % 2), big);
        for (int j = 0; j < v % 2; ++j) put(s, int16_t(-5), big);
        put(s, double(kY[v]), big);
        put(s, int8_t(kX[v]), big);
        put(s, float(0.5), big);
      }
      put(s, uint8_t(2), big); put(s, 1.0, big); put(s, 2.0, big);
      for (const auto& f : kF) {
        put(s, int32_t(77), big);
        put(s, uint16_t(3), big);
        for (int i : f) put(s, uint16_t(i), big);
        put(s, uint8_t(2), big); put(s, 0.25f, big); put(s, 0.75f, big);
      }
      check_square(parse(s, "ply"));
    }
  }
}

TEST_CASE("ply binary: double coordinates keep every bit") {
  const double v[3][3] = {{0.1, 1e-300, -123456.78901234567}, {1.0 / 3.0, 2.0, 3.0}, {4.0, 5.0, 6.0}};
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                  "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  for (const auto& p : v) for (double c : p) put(s, c, false);
  put(s, uint8_t(3), false); put(s, uint32_t(2), false); put(s, uint32_t(1), false); put(s, uint32_t(0), false);
  const auto m = parse(s, "ply");
  for (int i = 0; i < 3; ++i) {
    CHECK(m.x[i] == v[i][0]);
    CHECK(m.y[i] == v[i][1]);
    CHECK(m.z[i] == v[i][2]);
  }
  CHECK(face_of(m, 0) == std::vector<int32_t>{2, 1, 0});
}

TEST_CASE("ply: polygon faces and a vertex-only file") {
  const char* quad =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
  const auto m = parse(quad, "ply");
  CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2, 3});
  CHECK_FALSE(m.is_triangle_mesh());
  const auto pts = parse("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                         "end_header\n1 2 3\n4 5 6\n",
                         "ply");
  CHECK(pts.num_vertices() == 2);
  CHECK(pts.num_faces() == 0);
  CHECK(pts.z[1] == 6.0);
}

TEST_CASE("ply: header problems are named") {
  auto e = parse_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n", "ply");
  CHECK(e.code == locus::ErrorCode::BadInput);
  CHECK(e.has("x, y, z"));
  e = parse_error("ply\nformat binary_middle_endian 1.0\nend_header\n", "ply");
  CHECK(e.has("t.ply:2:"));
  CHECK(e.has("unknown PLY format"));
  e = parse_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", "ply");
  CHECK(e.has("t.ply:4:"));
  CHECK(e.has("unknown PLY property type"));
  e = parse_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nend_header\n", "ply");
  CHECK(e.has("appears twice"));
  e = parse_error("ply\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", "ply");
  CHECK(e.has("no 'format'"));
  e = parse_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 1\nproperty int vertex_indices\nend_header\n0 0 0\n1\n",
                  "ply");
  CHECK(e.has("must be a list"));
  e = parse_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 1\nproperty list float int vertex_indices\nend_header\n0 0 0\n1\n",
                  "ply");
  CHECK(e.has("list count type"));
  e = parse_error("plyx\nformat ascii 1.0\n", "ply");
  CHECK(e.has("not a PLY file"));
}
