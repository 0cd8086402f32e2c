// The command-line contract at its edges (README "exit status", DESIGN.md
// "Outputs are the product"): every output target is checked before any work
// and "wrote" is logged only for files that stay; refusals that depend on the
// file's contents exit 3 (2 is bad usage, checked before the file is read);
// coordinates at scales whose areas overflow or underflow are refused naming
// the scale and the range that works; an absurd heat time is refused naming
// its limit; --max-memory bounds the subdivision and the data derived from it.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

locus::Mesh scaled(locus::Mesh m, double s) {
  for (auto* c : {&m.x, &m.y, &m.z})
    for (double& v : *c) v *= s;
  return m;
}

locus::Mesh octahedron() {
  locus::Mesh m;
  const double p[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const auto& q : p) m.add_vertex(q[0], q[1], q[2]);
  const int32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (const auto& t : f) m.add_face(locus::ConstView<int32_t>(t, 3));
  return m;
}

}  // namespace

TEST_CASE("contract: cvt checks --labels and --sites-out before any work; 'wrote' only for committed files") {
  if (!have_locus()) return;
  Scratch dir("gaps-targets");
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, locus::make_icosphere(3));
  const std::string remesh = dir / "remesh.obj";
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--labels", dir / "no/such/folder/labels.ply"},
        std::vector<std::string>{"--labels", dir / "labels.txt"},
        std::vector<std::string>{"--sites-out", dir / "no/such/folder/sites.ply"},
        std::vector<std::string>{"--sites-out", dir / "sites.png"}}) {
    CAPTURE(bad[1]);
    std::vector<std::string> args = {"cvt", sphere, "--sites", "40", "--iters", "2", "-o", remesh};
    args.insert(args.end(), bad.begin(), bad.end());
    const Run r = run_locus(dir, args);
    CHECK(r.status == 2);
    CHECK_FALSE(has(r.err, "wrote"));             // nothing was written, nothing is announced
    CHECK_FALSE(has(r.err, "Lloyd"));             // refused before the work: no progress lines
    CHECK_FALSE(fs::exists(remesh));
  }
  // A run that succeeds announces each file once, after it is in place.
  const Run ok = run_locus(dir, {"cvt", sphere, "--sites", "40", "--iters", "2", "-o", remesh, "--labels",
                                 dir / "labels.ply", "--sites-out", dir / "sites.ply"});
  REQUIRE_MESSAGE(ok.status == 0, ok.err);
  for (const std::string& f : {remesh, dir / "labels.ply", dir / "sites.ply"}) {
    CHECK(fs::exists(f));
    CHECK(has(ok.err, "wrote " + f));
  }
}

TEST_CASE("contract: refusals that depend on the file's contents exit 3, usage errors stay 2") {
  if (!have_locus()) return;
  Scratch dir("gaps-exit3");
  const std::string tri = dir / "single_tri.off";
  write_text(tri, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const std::string two = dir / "two_comp.off";
  write_text(two, "OFF\n6 2 0\n0 0 0\n1 0 0\n0 1 0\n5 0 0\n6 0 0\n5 1 0\n3 0 1 2\n3 3 4 5\n");
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, locus::make_icosphere(4));  // 5120 faces: 9 subdivisions overflow int32 indices

  // More sites than vertices: the remesh runs on a subdivision, as many
  // vertices as asked; unless that subdivision cannot be indexed.
  const Run sites = run_locus(dir, {"cvt", tri, "--sites", "50", "--json"});
  REQUIRE_MESSAGE(sites.status == 0, sites.err);
  CHECK(has(sites.err, "--sites 50 exceeds the 3 vertices of the mesh"));
  const auto rem = sites.json()["remesh"];
  CHECK(rem["delivered"].get<int>() >= 49);
  CHECK(rem["delivered"].get<int>() <= 51);
  CHECK(rem["manifold"].get<bool>());
  CHECK(rem["boundary_loops"].get<int>() == 1);
  CHECK(rem["genus"].get<int>() == 0);
  const Run huge = run_locus(dir, {"cvt", tri, "--sites", "100000000"});
  CHECK(huge.status == 3);
  CHECK(has(huge.err, "--sites 100000000 on 3 vertices needs"));
  // Too few sites for the components are raised to their count, and said.
  const Run comps = run_locus(dir, {"cvt", two, "--sites", "1", "--json"});
  CHECK(comps.status == 0);
  CHECK(has(comps.err, "--sites 1 raised to 2"));
  CHECK(comps.json()["remesh"]["requested"].get<int>() == 1);
  const Run sub = run_locus(dir, {"info", sphere, "--subdivide", "9"});
  CHECK(sub.status == 3);
  CHECK(has(sub.err, "1342177280 faces"));
  const Run source = run_locus(dir, {"geodesic", sphere, "--source", "99999"});
  CHECK(source.status == 3);
  CHECK(has(source.err, "--source 99999 is not a vertex"));
  // What can be told without the file stays bad usage.
  CHECK(run_locus(dir, {"cvt", tri, "--sites", "0"}).status == 2);
  CHECK(run_locus(dir, {"geodesic", sphere, "--source", "0", "--t", "abc"}).status == 2);
}

TEST_CASE("contract: coordinates whose areas overflow or underflow are refused naming the scale and the range") {
  if (!have_locus()) return;
  Scratch dir("gaps-scale");
  const locus::Mesh unit = locus::make_icosphere(3);
  for (const double s : {1e155, 1e160, 1e300, 1e-155, 1e-170, 1e-300}) {
    CAPTURE(s);
    const std::string path = dir / "scaled.off";
    locus::write_mesh(path, scaled(unit, s));
    for (const std::string command : {"geodesic", "heat", "factor"}) {
      CAPTURE(command);
      std::vector<std::string> args = {command, path};
      if (command == "geodesic") args.insert(args.end(), {"--source", "0"});
      if (command == "heat") args.insert(args.end(), {"--source", "0", "--target", "1"});
      const Run r = run_locus(dir, args);
      CHECK(r.status == 3);
      CHECK(has(r.err, s > 1 ? "overflow" : "underflow"));
      CHECK(has(r.err, "1e-150"));
      CHECK(has(r.err, "1e+150"));
      CHECK_FALSE(has(r.err, "zero area"));
      CHECK_FALSE(has(r.err, "positive definite"));
      CHECK_FALSE(has(r.err, "no area"));
    }
  }
  // Inside the range the answer is the unit sphere's, scaled, and no underflow is reported.
  const std::string unit_path = dir / "unit.off";
  locus::write_mesh(unit_path, unit);
  const Run base = run_locus(dir, {"geodesic", unit_path, "--source", "0", "--json"});
  REQUIRE_MESSAGE(base.status == 0, base.err);
  for (const double s : {1e149, 1e-149}) {
    CAPTURE(s);
    const std::string path = dir / "inside.off";
    locus::write_mesh(path, scaled(unit, s));
    const Run r = run_locus(dir, {"geodesic", path, "--source", "0", "--json"});
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = r.json();
    CHECK(j["heat_underflow_vertices"] == 0);
    CHECK_FALSE(has(r.err, "warning"));
    CHECK(j["max_distance"].get<double>() / s == doctest::Approx(base.json()["max_distance"].get<double>()).epsilon(1e-9));
  }
}

TEST_CASE("contract: an absurd heat time is refused naming the limit; no negative distance is valid") {
  if (!have_locus()) return;
  Scratch dir("gaps-t");
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, locus::make_icosphere(3));
  for (const std::string t : {"1e300h2", "1e20h2", "1e300"}) {
    CAPTURE(t);
    const Run r = run_locus(dir, {"geodesic", sphere, "--source", "0", "--t", t, "-o", dir / "d.ply"});
    CHECK(r.status == 2);
    CHECK(has(r.err, "at most"));
    CHECK_FALSE(fs::exists(dir / "d.ply"));
  }
  // At the largest time allowed every valid distance is >= 0.
  const Run r = run_locus(dir, {"geodesic", sphere, "--source", "0", "--t", "1e6h2", "-o", dir / "d.ply"});
  REQUIRE_MESSAGE(r.status == 0, r.err);
  const std::vector<double> d = vertex_property(dir / "d.ply", "distance");
  const std::vector<double> valid = vertex_property(dir / "d.ply", "valid");
  for (size_t i = 0; i < d.size(); ++i)
    if (valid[i] != 0) CHECK(d[i] >= 0);
}

TEST_CASE("contract: --max-memory bounds the subdivision and the data derived from it") {
  if (!have_locus()) return;
  Scratch dir("gaps-memory");
  const std::string octa = dir / "octahedron.off";
  locus::write_mesh(octa, octahedron());
  // 6 subdivisions: 32768 faces, 4 MB of mesh. Each of the heat method's two factors
  // needs about 9 MB and fits 16 MB; both, the operators and the per-triangle data do not.
  const Run r = run_locus(dir, {"geodesic", octa, "--source", "0", "--subdivide", "6", "--max-memory", "16M"});
  CHECK(r.status == 3);
  CHECK(has(r.err, "heat geodesic on 16386 vertices needs about"));
  CHECK(has(r.err, "--max-memory"));
  const Run small = run_locus(dir, {"info", octa, "--subdivide", "6", "--max-memory", "2M"});
  CHECK(small.status == 3);
  CHECK(has(small.err, "would make 32768 faces"));
  CHECK(has(small.err, "memory limit of"));
  const Run ok = run_locus(dir, {"geodesic", octa, "--source", "0", "--subdivide", "6", "--max-memory", "64M"});
  CHECK_MESSAGE(ok.status == 0, ok.err);
}
