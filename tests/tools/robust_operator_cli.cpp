// The operator choice through the one orchestration (the CLI builds its
// Session with --operator, engine/include/locus/engine/operator_choice.hpp):
// `locus heat|hks|adf|nncoords|voronoi` on an icosphere with fins (non-manifold
// edges) answer with --operator robust and auto, and refuse with cotan.
// Oracles: M - tL is symmetric, so the heat sent from a to b equals the heat
// sent from b to a; adf at v is (M - tL)^{-1}_vv, which the heat exchange of v
// with itself computes by another algorithm (a full solve, not etree subsets);
// natural-neighbor weights sum to 1; and the CLI's numbers are those of a
// Session built with the robust operator, bit for bit.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_defects_plant.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tests/engine/fold_mesh.hpp"
#include "tests/tools/cli_support.hpp"

namespace {

using namespace locus::test_cli;

// An icosphere (642 vertices) with 4 fins: 4 non-manifold edges.
std::string fin_sphere(const Scratch& dir) {
  const std::string path = dir / "fins.off";
  locus::write_mesh(path, locus::plant_mesh_defect(locus::make_icosphere(3), locus::PlantedDefect::Fin, 4));
  return path;
}

double heat_value(const Scratch& dir, const std::string& mesh, int a, int b) {
  const Run r = run_locus(dir, {"heat", mesh, "--source", std::to_string(a), "--target", std::to_string(b), "--method",
                                "full", "--operator", "robust", "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = r.json();
  CHECK(j["input"]["operator"]["used"] == "robust");
  return j["values"][0].get<double>();
}

}  // namespace

TEST_CASE("heat, adf, hks, nncoords, voronoi: --operator robust answers on a mesh with fins, cotan refuses") {
  if (!have_locus()) return;
  Scratch dir("robust-operator");
  const std::string mesh = fin_sphere(dir);
  const std::vector<std::vector<std::string>> commands = {
      {"heat", mesh, "--source", "0", "--target", "7"},
      {"adf", mesh, "--vertices", "0,7"},
      {"hks", mesh, "--ts", "1h2,4h2", "--vertices", "0,7"},
      {"nncoords", mesh, "--sites", "0,7,100,300", "--point", "10,0.2,0.3,0.5"},
      {"voronoi", mesh, "--random", "8"}};
  for (const auto& c : commands) {
    CAPTURE(c[0]);
    std::vector<std::string> cotan = c, robust = c, automatic = c;
    cotan.insert(cotan.end(), {"--operator", "cotan", "--json"});
    robust.insert(robust.end(), {"--operator", "robust", "--json"});
    automatic.push_back("--json");
    const Run refused = run_locus(dir, cotan);
    CHECK(refused.status == 3);
    CHECK(refused.err.find("non-manifold") != std::string::npos);
    const Run r = run_locus(dir, robust);
    REQUIRE(r.status == 0);
    CHECK(r.json()["input"]["operator"]["used"] == "robust");
    const Run a = run_locus(dir, automatic);
    REQUIRE(a.status == 0);
    CHECK(a.json()["input"]["operator"]["used"] == "robust");
  }

  // Symmetry of the exchange, across a fin's neighbourhood and far away.
  for (const auto& [a, b] : std::vector<std::pair<int, int>>{{0, 7}, {3, 500}, {641, 12}}) {
    const double ab = heat_value(dir, mesh, a, b), ba = heat_value(dir, mesh, b, a);
    CHECK(std::isfinite(ab));
    CHECK(ab > 0);
    CHECK(std::abs(ab - ba) <= 1e-12 * std::abs(ab));
  }
  // adf (etree subset solves) against the full solve of the exchange of v with itself.
  const Run adf = run_locus(dir, {"adf", mesh, "--vertices", "0,7,641", "--operator", "robust", "--json"});
  REQUIRE(adf.status == 0);
  const nlohmann::json aj = adf.json();
  const int ids[3] = {0, 7, 641};
  for (int k = 0; k < 3; ++k) {
    const double self = heat_value(dir, mesh, ids[k], ids[k]);
    CHECK(std::abs(aj["adf"][k].get<double>() - self) <= 1e-10 * self);
  }
  // Natural-neighbor weights: a partition of unity.
  const Run nn = run_locus(dir, {"nncoords", mesh, "--sites", "0,7,100,300", "--point", "10,0.2,0.3,0.5", "--operator",
                                 "robust", "--json"});
  REQUIRE(nn.status == 0);
  const nlohmann::json nj = nn.json();
  double sum = 0;
  for (const auto& w : nj["weights"]) sum += w.get<double>();
  CHECK(std::abs(sum - 1) <= 1e-9);
}

TEST_CASE("heat and hks --operator robust: the CLI's values are the robust Session's, bit for bit") {
  if (!have_locus()) return;
  Scratch dir("robust-operator-session");
  const std::string mesh = fin_sphere(dir);
  locus::SessionOptions so;
  so.mesh_operator = locus::OperatorChoice::Robust;
  const locus::Session s = locus::Session::from_file(mesh, {}, so);
  REQUIRE(s.operator_report().robust);

  const Run h = run_locus(dir, {"heat", mesh, "--source", "0,1", "--target", "7,300", "--operator", "robust", "--json"});
  REQUIRE(h.status == 0);
  locus::HeatRequest hq;
  hq.source = {0, 1};
  hq.target = {7, 300};
  const locus::HeatReport hr = s.heat(hq);
  const nlohmann::json hj = h.json();
  REQUIRE(hj["values"].size() == 2);
  CHECK(hj["values"][0].get<double>() == hr.values[0]);
  CHECK(hj["values"][1].get<double>() == hr.values[1]);

  const Run k = run_locus(dir, {"hks", mesh, "--ts", "1h2,0.01", "--vertices", "5", "--operator", "robust", "--json"});
  REQUIRE(k.status == 0);
  locus::HksRequest kq;
  kq.ts = {"1h2", "0.01"};
  kq.vertices = {5};
  const locus::HeatSignatureReport kr = s.hks(kq);
  const nlohmann::json kj = k.json();
  REQUIRE(kr.values.size() == 2);
  CHECK(kj["hks"][0][0].get<double>() == kr.values[0]);
  CHECK(kj["hks"][0][1].get<double>() == kr.values[1]);
}

TEST_CASE("geodesic: auto answers on the robust operator where the cotan heat method fails; cotan refuses") {
  if (!have_locus()) return;
  Scratch dir("robust-operator-fallback");
  const std::string mesh = dir / "fold.off";
  locus::write_mesh(mesh, locus::test::fold_mesh());
  const Run refused = run_locus(dir, {"geodesic", mesh, "--source", "0", "--operator", "cotan"});
  CHECK(refused.status == 4);
  CHECK(refused.err.find("negative") != std::string::npos);
  const Run r = run_locus(dir, {"geodesic", mesh, "--source", "0", "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = r.json();
  CHECK_FALSE(j["input"].contains("operator"));  // the mesh is clean: auto's cotan, reported as before
  CHECK(j["operator_fallback"].get<std::string>().find("robust operator") != std::string::npos);
  CHECK(r.err.find("warning: the cotan heat method failed") != std::string::npos);
  // The numbers of a Session on the robust operator, bit for bit.
  locus::SessionOptions so;
  so.mesh_operator = locus::OperatorChoice::Robust;
  locus::GeodesicRequest req;
  req.source = 0;
  const locus::GeodesicReport robust = locus::Session::from_file(mesh, {}, so).geodesic(req);
  CHECK(j["max_distance"].get<double>() == robust.max_distance);
}

TEST_CASE("geodesic on cheese.off: the robust operator's shallow dips below zero are set to 0 and reported") {
  // Both operators' Poisson solutions dip below zero near a few badly shaped
  // triangles of this genus-133 mesh (cotan -2.0e-4, robust -4.8e-5; h = 7.9e-3).
  const std::string mesh = LOCUS_MESH_CACHE_DIR "/cheese.off";
  if (!have_locus() || !std::filesystem::exists(mesh)) return;
  Scratch dir("robust-operator-dips");
  const Run r = run_locus(dir, {"geodesic", mesh, "--source", "0", "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = r.json();
  bool dipped = false;
  for (const auto& w : j["warnings"]) dipped = dipped || w.get<std::string>().find("dipped below zero") != std::string::npos;
  CHECK(dipped);
  // The same query through a Session on the robust operator: every distance finite and >= 0, 0 at the source.
  locus::SessionOptions so;
  so.mesh_operator = locus::OperatorChoice::Robust;
  locus::GeodesicRequest req;
  req.source = 0;
  const locus::GeodesicReport g = locus::Session::from_file(mesh, {}, so).geodesic(req);
  CHECK(g.distance[0] == 0.0);
  bool ok = true;
  for (double d : g.distance) ok = ok && std::isfinite(d) && d >= 0.0;
  CHECK(ok);
  CHECK(j["max_distance"].get<double>() == g.max_distance);
  const Run cotan = run_locus(dir, {"geodesic", mesh, "--source", "0", "--operator", "cotan"});
  CHECK(cotan.status == 4);  // the cotan operator asked for keeps the strict check
}

TEST_CASE("geodesic on a polygon mesh whose polygon operators cannot be built: auto answers on the triangulation") {
  // corner_poly.off: a hexagon whose virtual vertex lies on one of its edges.
  const std::string mesh = LOCUS_MESH_CACHE_DIR "/corner_poly.off";
  if (!have_locus() || !std::filesystem::exists(mesh)) return;
  Scratch dir("polygon-fallback");
  const Run r = run_locus(dir, {"geodesic", mesh, "--source", "0", "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = r.json();
  CHECK(j["operator_fallback"].get<std::string>().find("polygon operators failed") != std::string::npos);
  CHECK(r.err.find("warning: the polygon operators failed") != std::string::npos);
  // The same through a Session with auto (Session defaults): the distance from vertex 0 at
  // (0, 2, 1) to vertex 2 at (2, 0, 1) across the flat top (z = 1) is the straight line,
  // 2 sqrt 2, within the heat method's error on so coarse a mesh.
  locus::GeodesicRequest req;
  req.source = 0;
  const locus::GeodesicReport g = locus::Session::from_file(mesh, {}, {}).geodesic(req);
  CHECK(g.distance[0] == 0.0);
  CHECK(std::abs(g.distance[2] - 2 * std::sqrt(2.0)) < 0.25 * 2 * std::sqrt(2.0));
  CHECK(j["max_distance"].get<double>() == g.max_distance);
}
