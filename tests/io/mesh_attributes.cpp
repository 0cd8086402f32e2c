// Vertex attributes of a PLY input (io/include/locus/mesh_io.hpp
// MeshAttributes): normals, colours and a custom property are
// read with their types, and written back unchanged, float positions as float.
// The input fixture is hand-written text, not produced by locus' writer.
#include <doctest/doctest.h>

#include <string>

#include "tests/io/io_test_support.hpp"

namespace {

const char* kPly =
    "ply\nformat ascii 1.0\nelement vertex 4\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    "property double quality\nproperty short tag\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0  0 0 1  255 0 0  0.5 -3\n"
    "1 0 0  0 0 1  0 255 0  1.25 7\n"
    "1 1 0  0 0 1  0 0 255  2.125 -32768\n"
    "0 1 0  0 0 1  10 20 30 3.0625 32767\n"
    "3 0 1 2\n3 0 2 3\n";

}  // namespace

TEST_CASE("mesh attributes: PLY vertex properties are read with their types and written back") {
  locus::MeshAttributes attrs;
  const locus::Mesh m = locus::read_mesh_from_memory(kPly, std::string(kPly).size(), "ply", "a.ply", {}, &attrs);
  CHECK(attrs.float_positions);
  REQUIRE(attrs.vertex.size() == 8);
  using T = locus::VertexProperty::Type;
  const std::string names[] = {"nx", "ny", "nz", "red", "green", "blue", "quality", "tag"};
  const T types[] = {T::Float, T::Float, T::Float, T::UInt8, T::UInt8, T::UInt8, T::Double, T::Int16};
  for (size_t k = 0; k < 8; ++k) {
    CHECK(attrs.vertex[k].name == names[k]);
    CHECK(attrs.vertex[k].type == types[k]);
    CHECK(attrs.vertex[k].values.size() == 4);
  }
  CHECK(attrs.vertex[3].values[0] == 255);
  CHECK(attrs.vertex[6].values[2] == 2.125);
  CHECK(attrs.vertex[7].values[2] == -32768);

  for (bool binary : {true, false}) {
    CAPTURE(binary);
    const std::string path = (locus_test::scratch_dir() / (binary ? "attrs_bin.ply" : "attrs_ascii.ply")).string();
    locus::WriteOptions wo;
    wo.vertex_properties = attrs.vertex;
    wo.float_positions = attrs.float_positions;
    wo.binary = binary;
    locus::write_mesh(path, m, wo);
    locus::MeshAttributes back;
    const locus::Mesh m2 = locus::read_mesh(path, {}, &back);
    CHECK(m2.x == m.x);
    CHECK(m2.face_vertices == m.face_vertices);
    CHECK(back.float_positions);
    REQUIRE(back.vertex.size() == attrs.vertex.size());
    for (size_t k = 0; k < attrs.vertex.size(); ++k) {
      CHECK(back.vertex[k].name == attrs.vertex[k].name);
      CHECK(back.vertex[k].type == attrs.vertex[k].type);
      CHECK(back.vertex[k].values == attrs.vertex[k].values);
    }
  }
  // Values a type cannot hold are the caller's mistake.
  locus::WriteOptions bad;
  bad.vertex_properties = {{"red", T::UInt8, {0, 256, 0, 0}}};
  const auto e = locus_test::catch_error(
      [&] { locus::write_mesh((locus_test::scratch_dir() / "bad.ply").string(), m, bad); });
  CHECK(e.code == locus::ErrorCode::BadUsage);
  CHECK(e.has("uchar vertex property 'red'"));
}

TEST_CASE("mesh attributes: what an OFF keyword announces (N, C, ST) becomes vertex properties") {
  using T = locus::VertexProperty::Type;
  auto read = [](const std::string& text, locus::MeshAttributes& a) {
    return locus::read_mesh_from_memory(text.data(), text.size(), "off", "a.off", {}, &a);
  };
  auto find = [](const locus::MeshAttributes& a, const std::string& n) -> const locus::VertexProperty* {
    for (const auto& p : a.vertex)
      if (p.name == n) return &p;
    return nullptr;
  };
  // Integer colours: uchar red green blue (alpha when given); the comment after a line is no value.
  locus::MeshAttributes a;
  read("COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 0 128 0 # green\n0 1 0 0 0 7\n3 0 1 2\n", a);
  REQUIRE(find(a, "red"));
  CHECK(find(a, "red")->type == T::UInt8);
  CHECK(find(a, "green")->values[1] == 128);
  CHECK(find(a, "blue")->values[2] == 7);
  CHECK_FALSE(find(a, "alpha"));
  // Float colours with alpha, after normals (Geomview's order: N before C), then ST.
  locus::MeshAttributes b;
  read("STCNOFF\n3 1 0\n0 0 0 0 0 1 0.5 0.25 0 1 0.1 0.2\n1 0 0 0 0 1 0 0 1 1 0.3 0.4\n0 1 0 0 0 -1 1 1 1 0.5 0.5 0.6\n3 0 1 2\n", b);
  REQUIRE(find(b, "nz"));
  CHECK(find(b, "nz")->values[2] == -1);
  REQUIRE(find(b, "alpha"));
  CHECK(find(b, "red")->type == T::Float);
  CHECK(find(b, "red")->values[0] == 0.5);
  CHECK(find(b, "alpha")->values[2] == 0.5);
  CHECK(find(b, "u")->values[1] == 0.3);
  CHECK(find(b, "v")->values[2] == 0.6);
  CHECK(b.notes.empty());
  // Lines that disagree keep nothing, with a note naming the vertex.
  locus::MeshAttributes c;
  read("COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 0 128\n0 1 0 0 0 7\n3 0 1 2\n", c);
  CHECK(c.vertex.empty());
  REQUIRE(c.notes.size() == 1u);
  CHECK(c.notes[0].find("vertex 1") != std::string::npos);
  // A plain OFF has none, and no note.
  locus::MeshAttributes d;
  read("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", d);
  CHECK(d.vertex.empty());
  CHECK(d.notes.empty());
}
