// `locus geodesic` / `locus logmap` with --save / --load (the heat method's two
// factors in one file): the loaded run writes byte-identical per-vertex results
// to a run that factors (oracle: the same command without a cache), the log map
// reads the geodesic's file, and another t or another mesh is refused (exit 3).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

TEST_CASE("heat method cache CLI: geodesic and logmap load the factors bit-identically; mismatches exit 3") {
  if (!have_locus()) return;
  Scratch dir("heatcache");
  locus::Mesh m = locus::make_icosphere(4);
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, m);
  m.x[7] += 0.01;
  const std::string moved = dir / "moved.off";
  locus::write_mesh(moved, m);
  const std::string cache = dir / "heat.locus";

  const Run plain = run_locus(dir, {"geodesic", sphere, "--source", "3", "--json", "-o", dir / "plain.ply"});
  const Run saved =
      run_locus(dir, {"geodesic", sphere, "--source", "3", "--json", "-o", dir / "saved.ply", "--save", cache});
  const Run loaded =
      run_locus(dir, {"geodesic", sphere, "--source", "3", "--json", "-o", dir / "loaded.ply", "--load", cache});
  REQUIRE(plain.status == 0);
  REQUIRE(saved.status == 0);
  REQUIRE(loaded.status == 0);
  CHECK(loaded.json()["factor_cache"]["loaded"] == cache);
  CHECK(slurp(dir / "plain.ply") == slurp(dir / "loaded.ply"));
  CHECK(slurp(dir / "saved.ply") == slurp(dir / "loaded.ply"));
  CHECK(plain.json()["max_distance"].get<double>() > 2.0);  // half a great circle on the unit sphere is pi

  const Run lm_plain = run_locus(dir, {"logmap", sphere, "--center", "3", "--fraction", "0.1", "--json", "-o", dir / "lp.ply"});
  const Run lm_loaded = run_locus(
      dir, {"logmap", sphere, "--center", "3", "--fraction", "0.1", "--json", "-o", dir / "ll.ply", "--load", cache});
  REQUIRE(lm_plain.status == 0);
  REQUIRE(lm_loaded.status == 0);
  CHECK(slurp(dir / "lp.ply") == slurp(dir / "ll.ply"));

  const Run other_t = run_locus(dir, {"geodesic", sphere, "--source", "3", "--t-factor", "2", "--load", cache});
  CHECK(other_t.status == 3);
  CHECK(other_t.err.find(cache) != std::string::npos);
  const Run other_mesh = run_locus(dir, {"logmap", moved, "--center", "3", "--load", cache});
  CHECK(other_mesh.status == 3);
  const Run dem = run_locus(dir, {"logmap", sphere, "--center", "3", "--method", "dem", "--load", cache});
  CHECK(dem.status == 2);
}
