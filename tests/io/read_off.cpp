// Tests for io/src/read_off.cpp: header variants, counts layout, colours, comments,
// and the real CGAL meshes in cache/meshes (armadillo: 26002 vertices, 52000
// faces, as its header says and as CGAL documents it).
#include <doctest/doctest.h>

#include <filesystem>
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

TEST_CASE("off: plain cube of quads") {
  const char* text =
      "OFF\n# unit cube\n8 6 12\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  const auto m = parse(text, "off");
  REQUIRE(m.num_vertices() == 8);
  REQUIRE(m.num_faces() == 6);
  CHECK(m.x[6] == 1.0);
  CHECK(m.y[6] == 1.0);
  CHECK(m.z[6] == 1.0);
  CHECK(face_of(m, 5) == std::vector<int32_t>{3, 0, 4, 7});
  CHECK_FALSE(m.is_triangle_mesh());
}

TEST_CASE("off: header variants and count layouts give the same mesh") {
  const std::vector<std::string> texts = {
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1.5 0\n3 0 1 2\n",
      "OFF 3 1 0\n0 0 0\n1 0 0\n0 1.5 0\n3 0 1 2\n",
      "OFF\n3\n1\n0\n0 0 0\n1 0 0\n0 1.5 0\n3 0 1 2\n",
      "OFF\n3\n# comment between counts\n1 0\n0 0 0\n1 0 0\n0 1.5 0\n3 0 1 2\n",
      "OFF\n3 1\n0 0 0\n1 0 0\n0 1.5 0\n3 0 1 2\n",  // edge count omitted
      "3 1 0\n0 0 0\n1 0 0\n0 1.5 0\n3 0 1 2\n",     // keyword omitted (Geomview allows it)
      "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1.5 0 0 0 255 255\n3 0 1 2\n",
      "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1.5 0 0 0 1\n3 0 1 2\n",
      "CNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 1\n1 0 0 0 0 1 0 1 0 1\n0 1.5 0 0 0 1 0 0 1 1\n3 0 1 2\n",
      "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1.5 0 0 1\n3 0 1 2\n",
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1.5 0\n3 0 1 2 0.8 0.1 0.1\n",  // face colour
      "# leading comment\n\nOFF # trailing\n# mid\n3 1 0 # counts\n0 0 0\n\n1 0 0 # v1\n0 1.5 0\n# f\n3 0 1 2\n",
      "\xEF\xBB\xBFOFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1.5 0\r\n3 0 1 2\r\n",
  };
  for (const auto& t : texts) {
    CAPTURE(t);
    const auto m = parse(t, "off");
    REQUIRE(m.num_vertices() == 3);
    REQUIRE(m.num_faces() == 1);
    CHECK(m.y[2] == 1.5);
    CHECK(face_of(m, 0) == std::vector<int32_t>{0, 1, 2});
    CHECK(m.is_triangle_mesh());
  }
}

TEST_CASE("off: unsupported variants are refused by name") {
  auto e = parse_error("4OFF\n3 1 0\n0 0 0 0\n", "off");
  CHECK(e.code == locus::ErrorCode::BadInput);
  CHECK(e.has("only 3-D OFF"));
  e = parse_error("OFF BINARY\n", "off");
  CHECK(e.has("binary OFF"));
  e = parse_error("PLY\n3 1 0\n", "off");
  CHECK(e.has("expected an OFF header"));
}

TEST_CASE("off: zero faces is a point set") {
  const auto m = parse("OFF\n2 0 0\n0 0 0\n1 1 1\n", "off");
  CHECK(m.num_vertices() == 2);
  CHECK(m.num_faces() == 0);
}

TEST_CASE("off: every real mesh in cache/meshes loads or raises BadInput; armadillo is 26002 v / 52000 f") {
  namespace fs = std::filesystem;
  const fs::path dir = LOCUS_MESH_CACHE_DIR;
  if (!fs::is_directory(dir)) {
    MESSAGE("cache/meshes not present (run tools/fetch_meshes.sh); skipping the real-mesh check");
    return;
  }
  int loaded = 0, refused = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".off") continue;
    try {
      const auto m = locus::read_mesh(entry.path().string());
      CHECK(m.num_vertices() > 0);
      // Every face index is in range (the reader's contract).
      bool in_range = true;
      for (int32_t v : m.face_vertices) in_range = in_range && v >= 0 && v < m.num_vertices();
      CHECK(in_range);
      ++loaded;
    } catch (const locus::Error& e) {
      CHECK_MESSAGE(e.code() == locus::ErrorCode::BadInput, e.what());
      MESSAGE(e.what());
      ++refused;
    }
  }
  MESSAGE("cache/meshes: " << loaded << " loaded, " << refused << " refused with BadInput");
  CHECK(loaded > 0);
  const fs::path arma = dir / "armadillo.off";
  if (fs::exists(arma)) {
    const auto m = locus::read_mesh(arma.string());
    CHECK(m.num_vertices() == 26002);
    CHECK(m.num_faces() == 52000);
    CHECK(m.is_triangle_mesh());
    // First vertex as written in the file: "-52.9283 67.3194 -57.6314".
    CHECK(m.x[0] == -52.9283);
    CHECK(m.y[0] == 67.3194);
    CHECK(m.z[0] == -57.6314);
  }
}
