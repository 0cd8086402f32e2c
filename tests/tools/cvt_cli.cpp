// `locus cvt MESH` as users run it: the default diffusion time is 4h^2 (h the mean
// edge length, computed here from the mesh), --t h2 selects the thesis's h^2, the
// issue's JSON keys are present, and a bad --t exits 2.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

namespace {

// Mean length of the unique edges (the oracle for the JSON's h).
double mean_edge(const locus::Mesh& m) {
  std::set<std::pair<int32_t, int32_t>> edges;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(v[k], v[(k + 1) % 3]));
  }
  double sum = 0;
  for (const auto& [a, b] : edges) sum += std::hypot(m.x[a] - m.x[b], m.y[a] - m.y[b], m.z[a] - m.z[b]);
  return sum / static_cast<double>(edges.size());
}

}  // namespace

TEST_CASE("cvt CLI: default t = 4h^2, --t h2, the issue's JSON keys, bad --t exits 2") {
  if (!have_locus()) return;
  Scratch dir("cvt-cli");
  const locus::Mesh m = locus::make_icosphere(3);  // 642 vertices
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, m);
  const double h = mean_edge(m);

  const Run d = run_locus(dir, {"cvt", sphere, "--sites", "30", "--iters", "3", "--json"});
  REQUIRE_MESSAGE(d.status == 0, d.err);
  const auto j = d.json();
  CHECK(j["h"].get<double>() == doctest::Approx(h).epsilon(1e-9));
  CHECK(j["t"].get<double>() == doctest::Approx(4 * h * h).epsilon(1e-9));
  for (const char* k : {"init_s", "factor_s", "iter_s", "min_angle_deg", "mean_angle_deg", "area_cv"})
    CHECK_MESSAGE(j.contains(k), k);
  CHECK(j["mean_angle_deg"].get<double>() > 30);  // 30 sites on a sphere after 3 steps
  CHECK(j["mean_angle_deg"].get<double>() <= 60);

  const Run t1 = run_locus(dir, {"cvt", sphere, "--sites", "30", "--iters", "3", "--t", "h2", "--json"});
  REQUIRE_MESSAGE(t1.status == 0, t1.err);
  CHECK(t1.json()["t"].get<double>() == doctest::Approx(h * h).epsilon(1e-9));

  CHECK(run_locus(dir, {"cvt", sphere, "--sites", "30", "--t", "-1", "--json"}).status == 2);
}
