// `locus param MESH --center V --fraction f [--boundary neumann|circle]` as
// users run it: the circle boundary gives a flip-free map of a disk patch of a
// sphere, written as the patch mesh with one texture coordinate per vertex on
// the unit disk; the two boundary modes map the same patch; bad usage exits 2.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

TEST_CASE("param CLI: patch mode with --boundary circle and neumann") {
  if (!have_locus()) return;
  Scratch dir("param-patch");
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, locus::make_icosphere(4));
  const std::string out = dir / "patch.obj";
  const Run c = run_locus(dir, {"param", sphere, "--center", "17", "--fraction", "0.2", "--boundary", "circle", "-o",
                                out, "--json"});
  REQUIRE_MESSAGE(c.status == 0, c.err);
  const auto j = c.json();
  CHECK(j["boundary"] == "circle");
  CHECK(j["flipped_faces"] == 0);
  CHECK(j["degenerate_faces"] == 0);
  CHECK(j["euler_characteristic"] == 1);
  CHECK(j["boundary_loops"] == 1);
  CHECK(j["refinement_steps"].get<int>() >= 1);
  for (const char* k : {"n", "factor_s", "query_s"}) CHECK(j.contains(k));
  const int np = j["patch_vertices"].get<int>();
  CHECK(np >= static_cast<int>(0.2 * 2562) - 50);
  CHECK(np == j["interior_vertices"].get<int>() + j["boundary_vertices"].get<int>());

  // The written patch: np vertices, uv inside the unit disk (normalized), the
  // farthest at radius 1.
  const locus::Mesh pm = locus::read_mesh(out);
  CHECK(pm.num_vertices() == np);
  std::istringstream obj(slurp(out));
  std::string line;
  int vt = 0;
  double rmax = 0;
  while (std::getline(obj, line))
    if (line.rfind("vt ", 0) == 0) {
      std::istringstream ls(line.substr(3));
      double u = 0, v = 0;
      ls >> u >> v;
      rmax = std::max(rmax, std::hypot(u, v));
      ++vt;
    }
  CHECK(vt == np);
  CHECK(rmax == doctest::Approx(1.0).epsilon(1e-6));

  const Run n = run_locus(dir, {"param", sphere, "--center", "17", "--fraction", "0.2", "--json"});
  REQUIRE_MESSAGE(n.status == 0, n.err);
  CHECK(n.json()["boundary"] == "neumann");

  const Run bad = run_locus(dir, {"param", sphere, "--center", "17", "--boundary", "dirichlet", "--json"});
  CHECK(bad.status == 2);
  CHECK(bad.err.find("--boundary") != std::string::npos);
  const Run no_patch = run_locus(dir, {"param", sphere, "--boundary", "circle", "--json"});
  CHECK(no_patch.status == 2);
}
