// Tests for io/src/read_mesh.cpp: dispatch by extension over the fixtures in
// tests/data/io/, which hold the same square pyramid (4 triangles + a quad
// base) in OBJ, OFF, ascii PLY and big-endian binary PLY; the expected
// numbers are the pyramid written out by hand below.
#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "io_test_support.hpp"
#include "locus/mesh_io.hpp"

TEST_CASE("read_mesh: the same pyramid from every format") {
  const double X[5] = {0, 1, 1, 0, 0.5}, Y[5] = {0, 0, 1, 1, 0.5}, Z[5] = {0, 0, 0, 0, 1};
  const std::vector<int32_t> offsets = {0, 3, 6, 9, 12, 16};
  const std::vector<int32_t> corners = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 3, 2, 1};
  for (const char* file : {"pyramid.obj", "pyramid.off", "pyramid_ascii.ply", "pyramid_be.ply"}) {
    CAPTURE(file);
    const std::string path = locus_test::data_dir() + "/" + file;
    const locus::Mesh m = locus::read_mesh(path);
    REQUIRE(m.num_vertices() == 5);
    for (int v = 0; v < 5; ++v) {
      CHECK(m.x[v] == X[v]);
      CHECK(m.y[v] == Y[v]);
      CHECK(m.z[v] == Z[v]);
    }
    CHECK(m.face_offsets == offsets);
    CHECK(m.face_vertices == corners);
    CHECK_FALSE(m.is_triangle_mesh());
    CHECK(m.source == path);
  }
}

TEST_CASE("read_mesh_from_memory: format names are case-insensitive and may carry a dot") {
  const char* t = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  for (const char* fmt : {"obj", "OBJ", ".obj", "Obj"}) {
    CAPTURE(fmt);
    const auto m = locus::read_mesh_from_memory(t, std::strlen(t), fmt, "mem");
    CHECK(m.num_faces() == 1);
    CHECK(m.source == "mem");
  }
}
