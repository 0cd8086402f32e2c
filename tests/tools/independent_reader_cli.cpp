// Outputs read by a second, independent reader:
// for every command x extension that writes a mesh, the file locus wrote is
// read by locus' readers and by tests/tools/independent_reader.py (Python's
// standard library only, written from the format descriptions); both must
// find the same vertices, faces and per-vertex results (NaN where there is no
// value). OBJ texture coordinates and normals of the input (vt, vn) reach OBJ
// and PLY outputs.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

namespace {

const std::string kReader = LOCUS_TEST_DATA_DIR "/../tools/independent_reader.py";

bool have_python() { return std::system("python3 -c 'import json, struct' >/dev/null 2>&1") == 0; }

nlohmann::json python_read(const Scratch& dir, const std::string& path) {
  const std::string out = dir / "py.json";
  const std::string cmd = "python3 '" + kReader + "' '" + path + "' > '" + out + "'";
  REQUIRE_MESSAGE(std::system(cmd.c_str()) == 0, cmd);
  return nlohmann::json::parse(slurp(out));
}

// locus' reader and the Python reader agree on the file.
void check_same(const Scratch& dir, const std::string& path, const std::vector<std::string>& results) {
  CAPTURE(path);
  locus::MeshAttributes a;
  const locus::Mesh m = locus::read_mesh(path, {}, &a);
  const nlohmann::json py = python_read(dir, path);
  REQUIRE(py["vertices"] == m.num_vertices());
  REQUIRE(py["faces"].size() == static_cast<size_t>(m.num_faces()));
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto fv = m.face(f);
    REQUIRE(py["faces"][f].size() == fv.size());
    for (size_t k = 0; k < fv.size(); ++k) CHECK(py["faces"][f][k] == fv[k]);
  }
  for (const std::string& name : results) {
    CAPTURE(name);
    REQUIRE(py["properties"].contains(name));
    const locus::VertexProperty* p = nullptr;
    for (const auto& q : a.vertex)
      if (q.name == name) p = &q;
    REQUIRE(p);
    const auto& values = py["properties"][name];
    REQUIRE(values.size() == p->values.size());
    for (size_t v = 0; v < p->values.size(); ++v) {
      if (std::isnan(p->values[v])) {
        CHECK(values[v].is_null());
      } else {
        REQUIRE(values[v].is_number());
        CHECK(values[v].get<double>() == p->values[v]);
      }
    }
  }
}

}  // namespace

TEST_CASE("independent reader: every command x extension writes what a second reader finds") {
  if (!have_locus() || !have_python()) return;
  Scratch dir("independent");
  const std::string sphere = dir / "sphere.off", disk = dir / "disk.off";
  locus::write_mesh(sphere, locus::make_icosphere(2));
  locus::Mesh grid = locus::make_grid(6);
  for (int32_t v = 0; v < grid.num_vertices(); ++v) grid.z[v] = 0.05 * std::sin(3 * grid.x[v]);
  locus::write_mesh(disk, grid);
  struct Case {
    std::vector<std::string> args;  // without -o
    std::vector<std::string> exts;
    std::vector<std::string> results;  // properties in PLY / OBJ (OFF: colours)
  };
  const std::vector<Case> cases = {
      {{"geodesic", sphere, "--source", "0", "--fraction", "0.5"}, {"ply", "obj", "off"}, {"distance", "valid"}},
      {{"logmap", sphere, "--center", "0", "--fraction", "0.3"}, {"ply", "obj"}, {"u", "v", "distance", "valid"}},
      {{"adf", sphere, "--all"}, {"ply", "obj", "off"}, {"adf"}},
      {{"hks", sphere, "--ts", "1h2,10h2", "--all"}, {"ply", "obj"}, {"hks_0", "hks_1"}},
      {{"skinweights", sphere, "--handles", "0,100"}, {"ply", "obj", "off"}, {"w0", "w1"}},
      {{"deform", sphere, "--roi-seed", "0", "--handle", "0", "--offset", "0,0,0.1"}, {"ply", "obj", "off"}, {}},
      {{"cvt", sphere, "--sites", "30", "--iters", "2"}, {"ply", "obj", "off"}, {}},
      {{"param", disk}, {"ply", "obj"}, {"u", "v"}},
      {{"info", sphere}, {"ply", "obj", "off"}, {}},
  };
  for (const Case& c : cases)
    for (const std::string& ext : c.exts) {
      CAPTURE(c.args[0]);
      CAPTURE(ext);
      const std::string out = dir / (c.args[0] + "." + ext);
      std::vector<std::string> args = c.args;
      args.insert(args.end(), {"-o", out});
      const Run r = run_locus(dir, args);
      REQUIRE_MESSAGE(r.status == 0, r.err);
      // OFF holds the first result as colours: the Python reader finds them too.
      check_same(dir, out, ext == "off" ? std::vector<std::string>{} : c.results);
      if (ext == "off" && !c.results.empty()) {
        const nlohmann::json py = python_read(dir, out);
        CHECK(py["properties"].contains("red"));
      }
    }
  // What a format cannot hold is refused before any work (exit 2), the file untouched.
  write_text(dir / "keep.off", "keep");
  CHECK(run_locus(dir, {"logmap", sphere, "--center", "0", "-o", dir / "keep.off"}).status == 2);
  CHECK(run_locus(dir, {"voronoi", sphere, "--sites", "0,5", "-o", dir / "keep.off"}).status == 2);
  CHECK(run_locus(dir, {"heat", sphere, "--source", "0", "--target", "1", "-o", dir / "keep.ply"}).status == 2);
  CHECK(slurp(dir / "keep.off") == "keep");
}

TEST_CASE("independent reader: an OBJ's vt and vn reach OBJ and PLY outputs; a seam is named and dropped") {
  if (!have_locus() || !have_python()) return;
  Scratch dir("obj_attributes");
  // An octahedron with a vt and a vn per vertex, written by hand; corners name them (v/vt/vn).
  const std::string in = dir / "octa.obj";
  const double P[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int F[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  std::ostringstream s;
  for (const auto& p : P) s << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  // vt and vn in reverse vertex order, so an index mix-up shows.
  for (int v = 5; v >= 0; --v) s << "vt " << 0.1 * v << ' ' << 0.5 + 0.05 * v << '\n';
  for (int v = 5; v >= 0; --v) s << "vn " << P[v][0] << ' ' << P[v][1] << ' ' << P[v][2] << '\n';
  for (const auto& f : F) {
    s << 'f';
    for (int k = 0; k < 3; ++k) s << ' ' << f[k] + 1 << '/' << 6 - f[k] << '/' << 6 - f[k];
    s << '\n';
  }
  const std::string text = s.str();
  write_text(in, text);
  for (const std::string ext : {"obj", "ply"}) {
    CAPTURE(ext);
    const std::string out = dir / ("g." + ext);
    const Run r = run_locus(dir, {"geodesic", in, "--source", "0", "-o", out});
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const nlohmann::json py = python_read(dir, out);
    for (int v = 0; v < 6; ++v) {
      CHECK(py["properties"]["u"][v].get<double>() == doctest::Approx(0.1 * v));
      CHECK(py["properties"]["v"][v].get<double>() == doctest::Approx(0.5 + 0.05 * v));
      CHECK(py["properties"]["nx"][v].get<double>() == doctest::Approx(P[v][0]));
      CHECK(py["properties"]["nz"][v].get<double>() == doctest::Approx(P[v][2]));
    }
    CHECK(py["properties"].contains("distance"));
    check_same(dir, out, {"u", "v", "nx", "ny", "nz", "distance"});
  }
  const std::string obj = slurp(dir / "g.obj");
  CHECK(obj.find("\nvt ") != std::string::npos);
  CHECK(obj.find("\nvn ") != std::string::npos);
  // A seam: vertex 0 named with two different vt. Kept running, the UVs dropped with a note.
  std::string seam = text;
  const size_t at = seam.rfind("/6/6");  // the last corner of vertex 0 names another vt
  REQUIRE(at != std::string::npos);
  seam[at + 1] = '5';
  write_text(dir / "seam.obj", seam);
  const Run r = run_locus(dir, {"geodesic", dir / "seam.obj", "--source", "0", "-o", dir / "s.ply"});
  REQUIRE(r.status == 0);
  CHECK(r.err.find("seam") != std::string::npos);
  const nlohmann::json py = python_read(dir, dir / "s.ply");
  CHECK_FALSE(py["properties"].contains("u"));
  CHECK(py["properties"].contains("nx"));
}
