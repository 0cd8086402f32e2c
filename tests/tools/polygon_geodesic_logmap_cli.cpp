// `locus geodesic` / `locus logmap` on polygon meshes
// (whole-mesh heat method on the polygon operators; oracle: the great-circle
// distance on a cube-sphere), the log map's injectivity radius and
// --clip-injective (oracle: the clipped map has no flipped triangle), and the
// underflow warning (never silent: stderr and JSON).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

TEST_CASE("geodesic/logmap CLI: polygon meshes, injectivity radius, underflow warning") {
  if (!have_locus()) return;
  Scratch dir("polygon_geodesic_logmap");
  const std::string quads = dir / "quads.obj";
  locus::write_mesh(quads, locus::make_cube_sphere(8));  // 384 quads, vertex 0 a cube corner
  const Run g = run_locus(dir, {"geodesic", quads, "--source", "0", "--json"});
  REQUIRE(g.status == 0);
  CHECK(g.json()["method"] == "heat-full-polygon");
  CHECK(std::abs(g.json()["max_distance"].get<double>() - M_PI) < 0.1);  // to the antipodal corner
  // Localized: no polygon path yet, so the quads are triangulated on load.
  const Run gl = run_locus(dir, {"geodesic", quads, "--source", "0", "--fraction", "0.5", "--json"});
  REQUIRE(gl.status == 0);
  CHECK(gl.json()["method"] == "heat-local");
  CHECK(gl.json()["input"]["triangulated"]["polygons"] == 384);
  const Run lm = run_locus(dir, {"logmap", quads, "--center", "0", "--fraction", "0.2", "--json"});
  REQUIRE(lm.status == 0);
  CHECK(lm.json()["method"] == "heat-full-polygon");
  CHECK(lm.json()["flipped_polygons"] == 0);
  const Run dem = run_locus(dir, {"logmap", quads, "--center", "0", "--method", "dem", "--json"});
  REQUIRE(dem.status == 0);
  CHECK(dem.json()["input"]["triangulated"]["polygons"] == 384);

  // Injectivity: the whole sphere folds around the antipode; clipped, nothing is flipped.
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, locus::make_icosphere(3));
  const Run whole = run_locus(dir, {"logmap", sphere, "--center", "5", "--fraction", "1", "--json"});
  REQUIRE(whole.status == 0);
  REQUIRE(whole.json()["flipped_triangles"].get<int64_t>() > 0);
  const double r = whole.json()["injectivity_radius"].get<double>();
  CHECK(r > 2.0);
  const Run clipped = run_locus(dir, {"logmap", sphere, "--center", "5", "--fraction", "1", "--clip-injective", "--json"});
  REQUIRE(clipped.status == 0);
  CHECK(clipped.json()["flipped_triangles"] == 0);
  CHECK(clipped.json()["clipped_vertices"].get<int64_t>() > 0);
  const Run small = run_locus(dir, {"logmap", sphere, "--center", "5", "--fraction", "0.1", "--json"});
  CHECK(small.json()["injectivity_radius"].is_null());

  // Underflow: warned, with a t that avoids it; none at the default t.
  const Run tiny = run_locus(dir, {"geodesic", sphere, "--source", "5", "--t-factor", "1e-20", "--json"});
  REQUIRE(tiny.status == 0);
  CHECK(tiny.json()["heat_underflow_vertices"].get<int64_t>() > 0);
  CHECK(tiny.json()["warnings"].size() == 1);
  CHECK(tiny.err.find("warning: the heat underflowed") != std::string::npos);
  const Run fine = run_locus(dir, {"geodesic", sphere, "--source", "5", "--json"});
  CHECK(fine.json()["heat_underflow_vertices"] == 0);
  CHECK_FALSE(fine.json().contains("warnings"));
}
