// `locus cvt --fit-sigma S` and the diagnostic JSON of the centroid fit: the weighted
// refit is on by default (sigma 1) and changes where the sites go (--fit-sigma 0 is
// the unweighted fit of earlier sessions); centroid_bias_h has one value per
// iteration, non-negative and below a cell's size; min_angle_sites names the three
// sites of the worst dual triangle, whose smallest angle (law of cosines on the
// reported positions) is min_angle_deg; a negative sigma exits 2.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

TEST_CASE("cvt CLI: --fit-sigma (default 1, 0 = unweighted), centroid_bias_h, min_angle_sites") {
  if (!have_locus()) return;
  Scratch dir("cvt-fit-sigma-cli");
  const locus::Mesh m = locus::make_icosphere(3);  // 642 vertices
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, m);

  const Run d = run_locus(dir, {"cvt", sphere, "--sites", "30", "--iters", "4", "--json"});
  REQUIRE_MESSAGE(d.status == 0, d.err);
  const Run s1 = run_locus(dir, {"cvt", sphere, "--sites", "30", "--iters", "4", "--fit-sigma", "1", "--json"});
  REQUIRE_MESSAGE(s1.status == 0, s1.err);
  const Run s0 = run_locus(dir, {"cvt", sphere, "--sites", "30", "--iters", "4", "--fit-sigma", "0", "--json"});
  REQUIRE_MESSAGE(s0.status == 0, s0.err);
  const auto jd = d.json(), j1 = s1.json(), j0 = s0.json();
  CHECK(jd["mean_angle_deg"].get<double>() == j1["mean_angle_deg"].get<double>());  // the default is 1
  CHECK(jd["energy"] == j1["energy"]);
  CHECK(j0["energy"] != j1["energy"]);  // the refit moves the sites

  const auto bias = jd["centroid_bias_h"];
  REQUIRE(bias.size() == 4);
  for (const auto& b : bias) {
    CHECK(b.get<double>() >= 0);
    CHECK(b.get<double>() < 5);  // 30 cells on 642 vertices: a cell is ~4.6 edges across
  }

  const auto worst = jd["min_angle_sites"];
  REQUIRE(worst.size() == 3);
  double p[3][3];
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) p[k][c] = worst[k]["xyz"][c].get<double>();
  auto dist = [&](int a, int b) { return std::hypot(p[a][0] - p[b][0], p[a][1] - p[b][1], p[a][2] - p[b][2]); };
  double len[3] = {dist(1, 2), dist(0, 2), dist(0, 1)};
  std::sort(len, len + 3);
  const double deg = std::acos((len[1] * len[1] + len[2] * len[2] - len[0] * len[0]) / (2 * len[1] * len[2])) * 180 / M_PI;
  CHECK(deg == doctest::Approx(jd["min_angle_deg"].get<double>()).epsilon(1e-6));

  CHECK(run_locus(dir, {"cvt", sphere, "--sites", "30", "--fit-sigma", "-1", "--json"}).status == 2);
}
