// One orchestration: `locus adf|hks|heat|nncoords|voronoi`, locus::Session and the C API give
// bit-identical answers on armadillo. The CLI's values are read back from the
// PLY it writes (adf --all: doubles, exact) or from its JSON (hks, heat and
// nncoords: JSON numbers print the shortest text that reads back to
// the same double). The values themselves are checked against independent
// oracles in tests/pipelines/heat; here only their agreement across front ends.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "locus/engine/voronoi_request.hpp"
#include "locus/locus.h"
#include "locus/session.hpp"
#include "tests/tools/cli_support.hpp"

namespace {

using namespace locus::test_cli;

const std::string kArmadillo = LOCUS_MESH_CACHE_DIR "/armadillo.off";

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

std::vector<double> json_doubles(const nlohmann::json& j) {
  std::vector<double> out;
  for (const auto& x : j) {
    if (x.is_array())
      for (const auto& y : x) out.push_back(y.get<double>());
    else
      out.push_back(x.get<double>());
  }
  return out;
}

}  // namespace

TEST_CASE("adf: the CLI, the Session and the C API agree bit for bit (--all, --method selinv)") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-adf");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  const std::string out = dir / "adf.ply";
  const Run r = run_locus(dir, {"adf", kArmadillo, "--all", "--t", "2h2", "--method", "selinv", "--threads", "2",
                                "-o", out});
  REQUIRE(r.status == 0);
  locus::AdfRequest q;
  q.t = "2h2";
  q.all = true;
  q.method = "selinv";
  const locus::HeatSignatureReport session = s.adf(q);
  CHECK(same_bits(vertex_property(out, "adf"), session.values));
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  locus_adf_options o = locus_adf_options_default();
  o.t = "2h2";
  o.all = 1;
  o.method = "selinv";
  std::vector<double> capi(static_cast<size_t>(s.num_vertices()));
  double t = 0;
  locus_signature_report rep;
  REQUIRE(locus_adf_run(c, &o, capi.data(), &t, &rep, nullptr) == LOCUS_OK);
  CHECK(same_bits(capi, session.values));
  CHECK(t == session.t[0]);
  CHECK(rep.evaluated == s.num_vertices());
  CHECK(rep.etree_height == session.etree_height);
  locus_session_destroy(c);
}

TEST_CASE("hks and heat: the CLI's JSON, the Session and the C API agree bit for bit") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-hks");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);

  const Run r = run_locus(dir, {"hks", kArmadillo, "--ts", "1h2,0.001", "--vertices", "5,0,5", "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  locus::HksRequest q;
  q.ts = {"1h2", "0.001"};
  q.vertices = {5, 0, 5};
  const locus::HeatSignatureReport session = s.hks(q);
  CHECK(same_bits(json_doubles(j["hks"]), session.values));
  const char* ts[] = {"1h2", "0.001"};
  const int64_t vs[] = {5, 0, 5};
  locus_hks_options o = locus_hks_options_default();
  o.ts = ts;
  o.n_ts = 2;
  o.vertices = vs;
  o.n_vertices = 3;
  std::vector<double> capi(6);
  REQUIRE(locus_hks_run(c, &o, capi.data(), nullptr, nullptr, nullptr) == LOCUS_OK);
  CHECK(same_bits(capi, session.values));
  CHECK(session.values[0] == session.values[4]);  // vertex 5 twice, the same value

  const Run h = run_locus(dir, {"heat", kArmadillo, "--source", "0,1,2", "--target", "100,200", "--method", "union",
                                "--json"});
  REQUIRE(h.status == 0);
  const nlohmann::json hj = nlohmann::json::parse(h.out);
  locus::HeatRequest hq;
  hq.source = {0, 1, 2};
  hq.target = {100, 200};
  hq.method = "union";
  const locus::HeatReport hr = s.heat(hq);
  CHECK(same_bits(json_doubles(hj["values"]), hr.values));
  CHECK(hj["total"].get<double>() == hr.total);
  const int64_t src[] = {0, 1, 2}, dst[] = {100, 200};
  locus_heat_options ho = locus_heat_options_default();
  ho.source = src;
  ho.n_source = 3;
  ho.target = dst;
  ho.n_target = 2;
  ho.method = "union";
  std::vector<double> hc(2);
  locus_heat_report hrep;
  REQUIRE(locus_heat_run(c, &ho, hc.data(), &hrep, nullptr) == LOCUS_OK);
  CHECK(same_bits(hc, hr.values));
  CHECK(hrep.forward_columns == hr.forward_columns);
  locus_session_destroy(c);
}

TEST_CASE("nncoords: the CLI's JSON, the Session and the C API agree bit for bit") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-nncoords");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  const Run r = run_locus(dir, {"nncoords", kArmadillo, "--sites", "0,100,200,300,400,500", "--point",
                                "10,0.2,0.3,0.5", "--t", "2h2", "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  locus::NncoordsRequest q;
  q.sites = {0, 100, 200, 300, 400, 500};
  q.point = {10, {0.2, 0.3, 0.5}};
  q.t = "2h2";
  const locus::NncoordsReport session = s.nncoords(q);
  CHECK(same_bits(json_doubles(j["weights"]), session.weights));
  CHECK(j["cell_area"].get<double>() == session.cell_area);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  const int64_t sites[] = {0, 100, 200, 300, 400, 500};
  locus_nncoords_options o = locus_nncoords_options_default();
  o.sites = sites;
  o.n_sites = 6;
  o.point.face = 10;
  o.point.bary[0] = 0.2, o.point.bary[1] = 0.3, o.point.bary[2] = 0.5;
  o.t = "2h2";
  std::vector<double> w(6);
  locus_nncoords_report rep;
  REQUIRE(locus_nncoords_run(c, &o, w.data(), &rep, nullptr) == LOCUS_OK);
  CHECK(same_bits(w, session.weights));
  CHECK(rep.t == session.t);
  locus_session_destroy(c);
}

// The "v x y z" lines of an OBJ the CLI wrote (17 digits: the doubles exactly).
static std::vector<double> obj_points(const std::string& path) {
  std::vector<double> out;
  std::istringstream in(slurp(path));
  std::string tag;
  double x, y, z;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    if (ls >> tag && tag == "v" && ls >> x >> y >> z) out.insert(out.end(), {x, y, z});
  }
  return out;
}

TEST_CASE("voronoi: the CLI, locus::Session::voronoi and the C API agree bit for bit (random and vertex sites)") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-voronoi");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  const std::string out = dir / "v.obj";
  const Run r = run_locus(dir, {"voronoi", kArmadillo, "--random", "30", "--seed", "7", "-o", out, "--json"});
  REQUIRE(r.status == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  locus::VoronoiCommandRequest q;
  q.random = 30;
  q.seed = 7;
  const locus::VoronoiCommandReport session = s.voronoi(q);
  CHECK(same_bits(obj_points(out), session.points));
  CHECK(j["corners"].get<int64_t>() == session.corners);
  CHECK(j["empty_cells"].get<int64_t>() == session.empty_cells);
  locus_voronoi_options o = locus_voronoi_options_default();
  o.random = 30;
  o.seed = 7;
  std::vector<int32_t> labels(static_cast<size_t>(s.num_vertices()));
  locus_voronoi_report rep;
  REQUIRE(locus_voronoi_run(c, &o, labels.data(), &rep, nullptr) == LOCUS_OK);
  CHECK(labels == session.label);
  CHECK(rep.points == static_cast<int64_t>(session.points.size() / 3));
  const int64_t sites[] = {0, 500, 1000};
  o = locus_voronoi_options_default();
  o.sites = sites;
  o.n_sites = 3;
  REQUIRE(locus_voronoi_run(c, &o, labels.data(), nullptr, nullptr) == LOCUS_OK);
  locus::VoronoiCommandRequest v;
  v.sites = {0, 500, 1000};
  CHECK(labels == s.voronoi(v).label);
  CHECK(labels[500] == 1);  // a generator's own vertex is its cell's
  o.random = 5;  // both kinds of generators: refused
  CHECK(locus_voronoi_run(c, &o, labels.data(), nullptr, nullptr) == LOCUS_BAD_USAGE);
  locus_session_destroy(c);
}

TEST_CASE("adf, hks, heat: the engine's refusals reach every front end with one status") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-refusals");
  // Usage: checked before the file is read (exit 2), the same check in the Session and the C API.
  CHECK(run_locus(dir, {"adf", "no-such-file.off", "--all", "--vertices", "1"}).status == 2);
  CHECK(run_locus(dir, {"hks", "no-such-file.off", "--ts", "1h2,-1", "--all"}).status == 2);
  CHECK(run_locus(dir, {"heat", "no-such-file.off", "--source", "0", "--target", "1", "--t", "x"}).status == 2);
  locus::AdfRequest both;
  both.all = true;
  both.vertices = {1};
  CHECK_THROWS_AS(locus::check_request(both), locus::Error);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  locus_adf_options o = locus_adf_options_default();  // neither vertices nor all
  double v = 0;
  CHECK(locus_adf_run(c, &o, &v, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  const int64_t far[] = {1 << 30};
  o.vertices = far;
  o.n_vertices = 1;
  CHECK(locus_adf_run(c, &o, &v, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  // A vertex beyond the file's: exit 3 (the refusal depends on the file).
  CHECK(run_locus(dir, {"adf", kArmadillo, "--vertices", "1073741824"}).status == 3);
  locus_session_destroy(c);
}
