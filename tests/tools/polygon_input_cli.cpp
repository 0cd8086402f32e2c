// Polygon input: every triangle-only command accepts a quad
// mesh by triangulating it on load; results on the input's vertices equal
// those of the same command on the triangulated file, and -o writes them on
// the input's own quads; a face that cannot be triangulated is refused (exit
// 3) naming it; locus info still reports the face degrees.
// The quad torus is written here as OFF text, not by locus' writer.
#include <doctest/doctest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "locus/kernels/mesh/polygon_triangulation.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

namespace {

// A torus of n x m quads (radii 2 and 0.7), slightly twisted so that quads are non-planar.
std::string quad_torus_off(int n, int m) {
  std::ostringstream s;
  s.precision(17);
  s << "OFF\n" << n * m << ' ' << n * m << " 0\n";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m + 0.05 * std::sin(3 * u);
      s << (2 + 0.7 * std::cos(v)) * std::cos(u) << ' ' << (2 + 0.7 * std::cos(v)) * std::sin(u) << ' '
        << 0.7 * std::sin(v) << '\n';
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const int a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m, d = i * m + (j + 1) % m;
      s << "4 " << a << ' ' << b << ' ' << c << ' ' << d << '\n';
    }
  return s.str();
}

}  // namespace

// A localized geodesic (--fraction < 1) has no polygon path: it triangulates on
// load. (Whole-mesh geodesic and log maps run on the polygons themselves,
// tests/tools/polygon_geodesic_logmap_cli.cpp.)
TEST_CASE("polygon input: localized geodesic on quads equals it on their triangulation; -o keeps the quads") {
  if (!have_locus()) return;
  Scratch dir("polygon_input");
  const std::string quads = dir / "torus.off", tris = dir / "torus_tri.off";
  write_text(quads, quad_torus_off(16, 8));
  const locus::Mesh q = locus::read_mesh(quads);
  REQUIRE_FALSE(q.is_triangle_mesh());
  locus::write_mesh(tris, locus::triangulate_polygons(q, quads).mesh);
  for (const std::string ext : {"ply", "obj"}) {
    CAPTURE(ext);
    const std::string a = dir / ("q." + ext), b = dir / ("t." + ext);
    const Run rq = run_locus(dir, {"geodesic", quads, "--source", "3", "--fraction", "0.5", "-o", a, "--json"});
    REQUIRE_MESSAGE(rq.status == 0, rq.err);
    REQUIRE(run_locus(dir, {"geodesic", tris, "--source", "3", "--fraction", "0.5", "-o", b}).status == 0);
    CHECK(rq.json()["input"]["triangulated"]["polygons"] == 128);
    CHECK(rq.json()["input"]["triangulated"]["triangles"] == 256);
    locus::Mesh back = locus::read_mesh(a);
    if (ext == "ply") {  // the OBJ's '#vp' block is read back by the independent-reader test
      const std::vector<double> dq = vertex_property(a, "distance"), dt = vertex_property(b, "distance");
      REQUIRE(dq.size() == dt.size());
      for (size_t v = 0; v < dq.size(); ++v) CHECK((dq[v] == dt[v] || (std::isnan(dq[v]) && std::isnan(dt[v]))));
    }
    // The written faces are the file's quads, vertex for vertex.
    REQUIRE(back.num_faces() == q.num_faces());
    CHECK(back.face_vertices == q.face_vertices);
  }
  // info reports the file's faces, not triangles.
  const Run info = run_locus(dir, {"info", quads, "--json"});
  REQUIRE(info.status == 0);
  CHECK(info.json()["face_degree_histogram"]["4"] == 128);
}

TEST_CASE("polygon input: every triangle-only command runs on a quad mesh") {
  if (!have_locus()) return;
  Scratch dir("polygon_commands");
  const std::string quads = dir / "torus.off";
  write_text(quads, quad_torus_off(16, 8));
  const std::vector<std::vector<std::string>> cases = {
      {"geodesic", "--source", "0"},
      {"logmap", "--center", "0", "--fraction", "0.3"},
      {"adf", "--all"},
      {"hks", "--ts", "1h2,10h2", "--all"},
      {"heat", "--source", "0", "--target", "5,9"},
      {"factor"},
      {"voronoi", "--sites", "0,40,80"},
      {"cvt", "--sites", "20", "--iters", "2"},
      {"nncoords", "--sites", "0,40,80,120", "--point", "10,0.2,0.3,0.5"},
      {"skinweights", "--handles", "0,64"},
      {"deform", "--roi-seed", "0", "--handle", "0", "--offset", "0,0,0.1"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args{c[0], quads};
    args.insert(args.end(), c.begin() + 1, c.end());
    args.push_back("--json");
    CAPTURE(c[0]);
    const Run r = run_locus(dir, args);
    CHECK_MESSAGE(r.status == 0, r.err);
  }
  // Outputs on the input's vertices keep its quads (hks, cvt --labels, deform moves the vertices).
  REQUIRE(run_locus(dir, {"hks", quads, "--ts", "1h2,10h2", "--all", "-o", dir / "h.ply"}).status == 0);
  CHECK(locus::read_mesh(dir / "h.ply").face(0).size() == 4u);
  REQUIRE(run_locus(dir, {"deform", quads, "--roi-seed", "0", "--handle", "0", "--offset", "0,0,0.1", "-o", dir / "d.obj"}).status == 0);
  const locus::Mesh d = locus::read_mesh(dir / "d.obj");
  CHECK(d.face(0).size() == 4u);
  CHECK(d.z[0] != locus::read_mesh(quads).z[0]);
}

TEST_CASE("polygon input: a self-crossing face is refused naming it, and nothing is written") {
  if (!have_locus()) return;
  Scratch dir("polygon_bad");
  const std::string bad = dir / "bowtie.off", out = dir / "out.ply";
  // Face 1 is a bow-tie (its edges 0-1 and 2-3 cross).
  write_text(bad, "OFF\n6 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n3 0 1 2\n4 1 5 4 2\n");
  write_text(out, "keep me");
  // Localized: triangulated on load (the whole-mesh geodesic keeps polygons).
  const Run r = run_locus(dir, {"geodesic", bad, "--source", "0", "--fraction", "0.5", "-o", out});
  CHECK(r.status == 3);
  CHECK(r.err.find("face 1 of") != std::string::npos);
  CHECK(r.err.find("cross") != std::string::npos);
  CHECK(slurp(out) == "keep me");
  // The whole-mesh geodesic runs on the polygons themselves: the same refusal.
  const Run w = run_locus(dir, {"geodesic", bad, "--source", "0", "-o", out});
  CHECK(w.status == 3);
  CHECK(w.err.find("face 1 of") != std::string::npos);
  CHECK(w.err.find("cross") != std::string::npos);
  CHECK(slurp(out) == "keep me");
}
