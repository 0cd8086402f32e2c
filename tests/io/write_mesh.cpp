// Tests for io/src/write_mesh.cpp: write-then-read round trips in every format
// (exact for doubles, ascii included), uv and named vertex properties checked
// by decoding the written bytes here (not with locus's reader, which drops
// them), and caller mistakes refused with BadUsage.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io_test_support.hpp"
#include "locus/mesh_io.hpp"

using locus_test::catch_error;
using locus_test::scratch_dir;

namespace {

// Awkward doubles: not representable in short decimal, tiny, huge, negative zero.
locus::Mesh sample_mesh() {
  locus::Mesh m;
  m.add_vertex(0.1, 1.0 / 3.0, -2.0 / 7.0);
  m.add_vertex(1e-310, 123456789.123456789, -0.0);
  m.add_vertex(std::nextafter(1.0, 2.0), 6.02214076e23, 2.5);
  m.add_vertex(-1.7976931348623157e308, 4.9e-324, 0.3);
  m.add_vertex(7.0, 8.0, 9.0);
  const int32_t quad[4] = {0, 1, 2, 3};
  m.add_triangle(0, 1, 4);
  m.add_face(quad);
  return m;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void check_same(const locus::Mesh& a, const locus::Mesh& b) {
  REQUIRE(a.num_vertices() == b.num_vertices());
  for (int32_t v = 0; v < a.num_vertices(); ++v) {
    // Bitwise equality: -0.0 must stay -0.0, subnormals must survive.
    CHECK(std::memcmp(&a.x[v], &b.x[v], 8) == 0);
    CHECK(std::memcmp(&a.y[v], &b.y[v], 8) == 0);
    CHECK(std::memcmp(&a.z[v], &b.z[v], 8) == 0);
  }
  CHECK(a.face_offsets == b.face_offsets);
  CHECK(a.face_vertices == b.face_vertices);
}

}  // namespace

TEST_CASE("write_mesh: exact round trip through every format") {
  const auto m = sample_mesh();
  for (const char* name : {"rt_bin.ply", "rt_ascii.ply", "rt.obj", "rt.off", "RT_UPPER.PLY"}) {
    CAPTURE(name);
    const std::string path = (scratch_dir() / name).string();
    locus::WriteOptions opt;
    opt.binary = std::string(name) != "rt_ascii.ply";
    locus::write_mesh(path, m, opt);
    check_same(m, locus::read_mesh(path));
  }
}

TEST_CASE("write_mesh: binary PLY layout with uv and named properties, decoded by hand") {
  locus::Mesh m;
  m.add_vertex(1, 2, 3);
  m.add_vertex(4, 5, 6);
  m.add_vertex(7, 8, 9);
  m.add_triangle(0, 1, 2);
  const std::vector<double> uv = {0.0, 0.5, 1.0, 0.25, 0.125, 1.0};
  locus::WriteOptions opt;
  opt.uv = &uv;
  opt.vertex_properties.push_back({"heat", locus::VertexProperty::Type::Double, {0.1, 0.2, 0.3}});
  opt.vertex_properties.push_back({"weight", locus::VertexProperty::Type::Float, {1.5, 2.5, 3.5}});
  opt.vertex_properties.push_back({"label", locus::VertexProperty::Type::Int, {-1, 7, 2147483647}});
  const std::string path = (scratch_dir() / "props.ply").string();
  locus::write_mesh(path, m, opt);
  const std::string bytes = slurp(path);
  const size_t body = bytes.find("end_header\n");
  REQUIRE(body != std::string::npos);
  const std::string header = bytes.substr(0, body);
  CHECK(header.find("format binary_little_endian 1.0") != std::string::npos);
  CHECK(header.find("property double u\nproperty double v\n") != std::string::npos);
  CHECK(header.find("property double heat\nproperty float weight\nproperty int label\n") != std::string::npos);
  // Vertex record: x y z u v (5 doubles) heat (double) weight (float) label (int) = 60 bytes.
  const char* p = bytes.data() + body + std::strlen("end_header\n");
  const size_t rec = 5 * 8 + 8 + 4 + 4;
  for (int v = 0; v < 3; ++v) {
    const char* r = p + v * rec;
    double d[6];
    float w;
    int32_t lab;
    std::memcpy(d, r, 48);  // host is little endian (x86); the file is little endian
    std::memcpy(&w, r + 48, 4);
    std::memcpy(&lab, r + 52, 4);
    CHECK(d[0] == m.x[v]);
    CHECK(d[3] == uv[2 * v]);
    CHECK(d[4] == uv[2 * v + 1]);
    CHECK(d[5] == opt.vertex_properties[0].values[v]);
    CHECK(w == float(opt.vertex_properties[1].values[v]));
    CHECK(lab == int32_t(opt.vertex_properties[2].values[v]));
  }
  const char* f = p + 3 * rec;
  CHECK(static_cast<unsigned char>(f[0]) == 3);
  int32_t idx[3];
  std::memcpy(idx, f + 1, 12);
  CHECK(idx[0] == 0);
  CHECK(idx[2] == 2);
  CHECK(bytes.size() == body + std::strlen("end_header\n") + 3 * rec + 13);
  // And the reader still takes the file (it skips what it does not keep).
  CHECK(locus::read_mesh(path).z[2] == 9.0);
}

TEST_CASE("write_mesh: ascii PLY properties and OBJ vt / f a/a") {
  locus::Mesh m;
  m.add_vertex(0, 0, 0);
  m.add_vertex(1, 0, 0);
  m.add_vertex(0, 1, 0);
  m.add_triangle(0, 1, 2);
  const std::vector<double> uv = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  locus::WriteOptions opt;
  opt.uv = &uv;
  opt.binary = false;
  opt.vertex_properties.push_back({"k", locus::VertexProperty::Type::Int, {3, -4, 5}});
  const std::string ply = (scratch_dir() / "props_ascii.ply").string();
  locus::write_mesh(ply, m, opt);
  const std::string text = slurp(ply);
  CHECK(text.find("format ascii 1.0") != std::string::npos);
  CHECK(text.find("\n1 0 0 0.3 0.4 -4\n") != std::string::npos);
  CHECK(text.find("\n3 0 1 2\n") != std::string::npos);

  const std::string obj = (scratch_dir() / "uv.obj").string();
  locus::write_mesh(obj, m, opt);
  const std::string o = slurp(obj);
  CHECK(o.find("vt 0.1 0.2\nvt 0.3 0.4\nvt 0.5 0.6\n") != std::string::npos);
  CHECK(o.find("f 1/1 2/2 3/3\n") != std::string::npos);
  const auto back = locus::read_mesh(obj);
  CHECK(back.num_faces() == 1);
  CHECK(back.y[2] == 1.0);
}

TEST_CASE("write_mesh: large polygons switch the PLY count type to int") {
  locus::Mesh m;
  std::vector<int32_t> poly;
  for (int i = 0; i < 300; ++i) {
    m.add_vertex(std::cos(i * 0.02), std::sin(i * 0.02), 0);
    poly.push_back(i);
  }
  m.add_face(poly);
  const std::string path = (scratch_dir() / "bigpoly.ply").string();
  locus::write_mesh(path, m);
  CHECK(slurp(path).find("property list int int vertex_indices") != std::string::npos);
  check_same(m, locus::read_mesh(path));
}

TEST_CASE("write_mesh: caller mistakes are BadUsage") {
  const auto m = sample_mesh();
  const std::string dir = scratch_dir().string();
  auto e = catch_error([&] { locus::write_mesh(dir + "/x.stl", m); });
  CHECK(e.code == locus::ErrorCode::BadUsage);
  CHECK(e.has("unknown mesh file extension"));
  std::vector<double> short_uv(3, 0.0);
  locus::WriteOptions opt;
  opt.uv = &short_uv;
  e = catch_error([&] { locus::write_mesh(dir + "/x.ply", m, opt); });
  CHECK(e.code == locus::ErrorCode::BadUsage);
  CHECK(e.has("uv has 3 values"));
  locus::WriteOptions p;
  p.vertex_properties.push_back({"bad name", locus::VertexProperty::Type::Double, std::vector<double>(5, 0.0)});
  e = catch_error([&] { locus::write_mesh(dir + "/x.ply", m, p); });
  CHECK(e.has("printable without spaces"));
  p.vertex_properties[0] = {"n", locus::VertexProperty::Type::Int, {0, 1, 2.5, 3, 4}};
  e = catch_error([&] { locus::write_mesh(dir + "/x.ply", m, p); });
  CHECK(e.has("at vertex 2"));
  auto broken = m;
  broken.face_vertices[1] = 99;
  e = catch_error([&] { locus::write_mesh(dir + "/x.off", broken); });
  CHECK(e.has("references vertex 99"));
  auto nan_mesh = m;
  nan_mesh.y[3] = std::nan("");
  e = catch_error([&] { locus::write_mesh(dir + "/x.obj", nan_mesh); });
  CHECK(e.has("vertex 3 has a non-finite"));
  e = catch_error([&] { locus::write_mesh(dir + "/no/such/dir/x.off", m); });
  CHECK(e.code == locus::ErrorCode::BadUsage);
  CHECK(e.has("does not exist"));
}
