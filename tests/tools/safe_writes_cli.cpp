// The CLI's outputs under hostile conditions: an
// existing output survives every failed run byte for byte; outputs are checked
// before the input is read; -o in every format carries the result.
#include <doctest/doctest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

namespace {

std::set<std::string> names_in(const fs::path& d) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(d)) out.insert(e.path().filename().string());
  return out;
}

}  // namespace

TEST_CASE("safe writes: a failed run leaves an existing output byte-identical") {
  if (!have_locus()) return;
  Scratch dir("safe");
  const std::string mesh = dir / "sphere.off";
  locus::write_mesh(mesh, locus::make_icosphere(3));
  const fs::path out = dir.path / "out" / "g.ply";
  fs::create_directories(out.parent_path());
  const std::string old = "an older result the user keeps\n";
  std::ofstream(out) << old;

  // Fails after reading the mesh (vertex out of range, exit 3): nothing is written.
  CHECK(run_locus(dir, {"geodesic", mesh, "--source", "99999", "-o", out.string()}).status == 3);
  CHECK(slurp(out) == old);
  // A bad preview path is refused before any work, -o untouched.
  const Run bad_preview =
      run_locus(dir, {"geodesic", mesh, "--source", "0", "-o", out.string(), "--preview", dir / "no/such/p.png"});
  CHECK(bad_preview.status == 2);
  CHECK(bad_preview.err.find("does not exist") != std::string::npos);
  CHECK(slurp(out) == old);
  // A fifo as target: refused, still a fifo.
  REQUIRE(::mkfifo((dir.path / "out" / "pipe.ply").c_str(), 0644) == 0);
  CHECK(run_locus(dir, {"info", mesh, "-o", (dir.path / "out" / "pipe.ply").string()}).status == 2);
  CHECK(fs::is_fifo(dir.path / "out" / "pipe.ply"));
  CHECK(names_in(out.parent_path()) == std::set<std::string>{"g.ply", "pipe.ply"});
}

TEST_CASE("safe writes: a file-size limit (ulimit -f) fails with exit 3 and keeps the old file") {
  if (!have_locus()) return;
  Scratch dir("fsize");
  const std::string mesh = dir / "sphere.off";
  locus::write_mesh(mesh, locus::make_icosphere(5));  // 10k vertices: the PLY is ~500 KB
  const fs::path out = dir.path / "big.ply";
  const std::string old(90 * 1024, 'x');
  std::ofstream(out) << old;
  // The shell's limit is in 1 KiB blocks; the child inherits it (and the CLI ignores SIGXFSZ).
  const std::string script = "ulimit -f 256 && exec '" + kLocus + "' info '" + mesh + "' -o '" + out.string() + "'";
  const int status = std::system(("sh -c \"" + script + "\" 2>" + (dir / "err.txt")).c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 3);
  CHECK(slurp(dir / "err.txt").find("write failed") != std::string::npos);
  CHECK(slurp(out) == old);
  for (const auto& e : fs::directory_iterator(dir.path)) CHECK(e.path().filename().string()[0] != '.');
}

TEST_CASE("safe writes: factor cache beside an unrelated PATH.tmp, and two concurrent --save to one path") {
  if (!have_locus()) return;
  Scratch dir("savetmp"), cap1("save1"), cap2("save2");
  const std::string mesh = dir / "torus.off";
  locus::write_mesh(mesh, locus::make_torus(60, 30));
  const std::string cache = dir / "c.locus";
  std::ofstream(cache + ".tmp") << "unrelated";
  for (int round = 0; round < 3; ++round) {
    const pid_t a = start_locus(cap1, {"factor", mesh, "--save", cache});
    const pid_t b = start_locus(cap2, {"factor", mesh, "--save", cache});
    CHECK(wait_locus(cap1, a).status == 0);
    CHECK(wait_locus(cap2, b).status == 0);
    CHECK(run_locus(dir, {"factor", mesh, "--load", cache}).status == 0);
  }
  CHECK(slurp(cache + ".tmp") == "unrelated");
  CHECK(names_in(dir.path) == std::set<std::string>{"c.locus", "c.locus.tmp", "torus.off", "stdout.txt", "stderr.txt"});
}

TEST_CASE("outputs: geodesic -o .obj and .off carry the distances; NaN outside the patch") {
  if (!have_locus()) return;
  Scratch dir("geoout");
  const locus::Mesh sphere = locus::make_icosphere(4);  // unit sphere, 2562 vertices
  const std::string mesh = dir / "sphere.off";
  locus::write_mesh(mesh, sphere);
  REQUIRE(run_locus(dir, {"geodesic", mesh, "--source", "0", "--fraction", "0.2", "-o", dir / "g.obj"}).status == 0);
  REQUIRE(run_locus(dir, {"geodesic", mesh, "--source", "0", "-o", dir / "g.off"}).status == 0);

  // An independent reading of the OBJ comment block (not the project's reader).
  std::istringstream obj(slurp(dir / "g.obj"));
  std::string header;
  std::vector<std::pair<double, int>> rows;
  for (std::string line; std::getline(obj, line);) {
    if (line.rfind("#locus vertex-properties", 0) == 0) header = line;
    if (line.rfind("#vp ", 0) == 0) {
      std::istringstream ls(line.substr(4));
      std::string d;
      int valid = -1;
      ls >> d >> valid;
      rows.emplace_back(d == "nan" ? std::nan("") : std::stod(d), valid);
    }
  }
  CHECK(header == "#locus vertex-properties distance:double valid:int");
  REQUIRE(rows.size() == static_cast<size_t>(sphere.num_vertices()));
  const double sx = sphere.x[0], sy = sphere.y[0], sz = sphere.z[0];
  int inside = 0;
  double worst = 0;
  for (size_t v = 0; v < rows.size(); ++v) {
    const auto [d, valid] = rows[v];
    CHECK((valid == 1) == std::isfinite(d));  // no value: NaN, mask 0
    if (valid != 1) continue;
    ++inside;
    const double exact = std::acos(std::clamp(sx * sphere.x[v] + sy * sphere.y[v] + sz * sphere.z[v], -1.0, 1.0));
    worst = std::max(worst, std::abs(d - exact));
  }
  CHECK(inside > 400);
  CHECK(inside < 700);
  CHECK(worst < 0.05);  // heat method, t = h^2, h ~ 0.05: within an edge length

  // OFF: COFF with one colour per vertex (x y z r g b a).
  std::istringstream off(slurp(dir / "g.off"));
  std::string magic, line;
  std::getline(off, magic);
  CHECK(magic == "COFF");
  std::getline(off, line);  // "# colour: distance"
  CHECK(line == "# colour: distance");
  std::getline(off, line);  // counts
  std::getline(off, line);  // first vertex
  std::istringstream first(line);
  int fields = 0;
  for (std::string t; first >> t;) ++fields;
  CHECK(fields == 7);
  CHECK(locus::read_mesh(dir / "g.off").num_vertices() == sphere.num_vertices());
}

TEST_CASE("resources: --subdivide and --load beyond --max-memory are refused with exit 3 before allocating") {
  if (!have_locus()) return;
  Scratch dir("memlimit");
  const std::string mesh = dir / "sphere.off";
  locus::write_mesh(mesh, locus::make_icosphere(2));  // 320 faces
  // 320 * 4^8 = 21M faces: about 2.7 GiB, over a 100M limit.
  const Run big = run_locus(dir, {"info", mesh, "--subdivide", "8", "--max-memory", "100M"});
  CHECK(big.status == 3);
  CHECK(big.err.find("--subdivide 8") != std::string::npos);
  CHECK(big.err.find("--max-memory") != std::string::npos);
  const std::string cache = dir / "f.locus";
  REQUIRE(run_locus(dir, {"factor", mesh, "--save", cache}).status == 0);
  const Run load = run_locus(dir, {"factor", mesh, "--load", cache, "--max-memory", "1K"});
  CHECK(load.status == 3);
  CHECK(load.err.find("more than the memory limit") != std::string::npos);
  CHECK(run_locus(dir, {"factor", mesh, "--load", cache}).status == 0);
}
