// The scripting contract (README "Outputs"): every command's JSON has the same
// keys — version, threads (what ran), output, preview, timings {load_s,
// subdivide_s, total_s} — and one heat-time grammar: --t T with T absolute or
// a multiple of h^2, the heat method's older --t-factor C accepted as --t Ch2
// with a deprecation note (cvt: --centroid-t T, the older --t-centroid C as its alias).
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

TEST_CASE("scripting contract: every command's JSON has version, threads, output, preview and timings") {
  if (!have_locus()) return;
  Scratch dir("contract");
  const std::string sphere = dir / "sphere.off", disk = dir / "disk.off";
  locus::write_mesh(sphere, locus::make_icosphere(2));
  locus::Mesh grid = locus::make_grid(6);
  for (int32_t v = 0; v < grid.num_vertices(); ++v) grid.z[v] = 0.05 * std::sin(3 * grid.x[v]) * std::sin(2 * grid.y[v]);
  locus::write_mesh(disk, grid);
  const std::vector<std::vector<std::string>> cases = {
      {"info", sphere},
      {"perfect-laplacian", disk},
      {"param", disk},
      {"selfsupport", disk},
      {"factor", sphere},
      {"deform", sphere, "--roi-seed", "0", "--handle", "0", "--offset", "0,0,0.1"},
      {"adf", sphere, "--all"},
      {"hks", sphere, "--ts", "1h2,10h2", "--all"},
      {"heat", sphere, "--source", "0", "--target", "5"},
      {"voronoi", sphere, "--sites", "0,50,100"},
      {"nncoords", sphere, "--sites", "0,50,100,150", "--point", "10,0.2,0.3,0.5"},
      {"skinweights", sphere, "--handles", "0,100"},
      {"cvt", sphere, "--sites", "30", "--iters", "2"},
      {"logmap", sphere, "--center", "0", "--fraction", "0.3"},
      {"geodesic", sphere, "--source", "0"},
  };
  // Every command of `locus --help` (but the runner) is in the list: a new one must join the contract.
  const Run help = run_locus(dir, {"--help"});
  std::vector<std::string> listed;
  const size_t from = help.out.find("Subcommands:");
  REQUIRE(from != std::string::npos);
  std::istringstream lines(help.out.substr(from));
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line) && line.size() > 2 && line[0] == ' ') {
    const std::string name = line.substr(2, line.find(' ', 2) - 2);
    if (name != "run") listed.push_back(name);
  }
  std::vector<std::string> tested;
  for (const auto& c : cases) tested.push_back(c[0]);
  std::sort(listed.begin(), listed.end());
  std::sort(tested.begin(), tested.end());
  CHECK(listed == tested);
  for (const auto& c : cases) {
    CAPTURE(c[0]);
    std::vector<std::string> args = c;
    args.insert(args.end(), {"--json", "--threads", "2"});
    const Run r = run_locus(dir, args);
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = r.json();
    CHECK(j["command"] == c[0]);
    CHECK(j["version"].is_string());
    CHECK(j["threads"] == 2);
    CHECK(j.contains("output"));
    CHECK(j["output"].is_null());
    CHECK(j.contains("preview"));
    REQUIRE(j["timings"].is_object());
    for (const char* k : {"load_s", "subdivide_s", "total_s"}) {
      CAPTURE(k);
      REQUIRE(j["timings"].contains(k));
      CHECK(j["timings"][k].get<double>() >= 0);
    }
    CHECK(j["timings"]["total_s"].get<double>() >= j["timings"]["load_s"].get<double>());
  }
}

TEST_CASE("scripting contract: --t grammar of the heat method; --t-factor is a deprecated alias") {
  if (!have_locus()) return;
  Scratch dir("contract_t");
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, locus::make_icosphere(3));
  for (const char* cmd : {"geodesic", "logmap"}) {
    CAPTURE(cmd);
    const std::vector<std::string> base = {cmd, sphere, std::string(cmd) == "geodesic" ? "--source" : "--center", "0",
                                           "--json"};
    auto with = [&](std::vector<std::string> extra) {
      std::vector<std::string> a = base;
      a.insert(a.end(), extra.begin(), extra.end());
      return run_locus(dir, a);
    };
    const Run h2 = with({"--t", "2h2"});
    const Run alias = with({"--t-factor", "2"});
    REQUIRE_MESSAGE(h2.status == 0, h2.err);
    REQUIRE(alias.status == 0);
    CHECK(alias.err.find("deprecated") != std::string::npos);
    CHECK(h2.err.find("deprecated") == std::string::npos);
    const double h = h2.json()["h"], t = h2.json()["t"];
    CHECK(t == doctest::Approx(2 * h * h).epsilon(1e-12));
    CHECK(alias.json()["t"] == t);
    CHECK(alias.json()["max_distance"] == h2.json()["max_distance"]);
    // An absolute time gives that time.
    const Run abs = with({"--t", "0.01"});
    REQUIRE(abs.status == 0);
    CHECK(abs.json()["t"].get<double>() == doctest::Approx(0.01).epsilon(1e-12));
    // Both spellings, or a bad time: usage errors.
    CHECK(with({"--t", "2h2", "--t-factor", "2"}).status == 2);
    CHECK(with({"--t", "abc"}).status == 2);
    CHECK(with({"--t-factor", "-1"}).status == 2);
  }
}

TEST_CASE("scripting contract: cvt --centroid-t takes the --t grammar; --t-centroid C is its deprecated alias") {
  if (!have_locus()) return;
  Scratch dir("contract_tc");
  const std::string sphere = dir / "sphere.off";
  locus::write_mesh(sphere, locus::make_icosphere(3));
  auto cvt = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = {"cvt", sphere, "--sites", "20", "--iters", "2", "--json"};
    a.insert(a.end(), extra.begin(), extra.end());
    return run_locus(dir, a);
  };
  const Run plain = cvt({}), h2 = cvt({"--centroid-t", "2h2"}), alias = cvt({"--t-centroid", "2"});
  const Run abs = cvt({"--centroid-t", "0.01"});
  for (const Run* r : {&plain, &h2, &alias, &abs}) REQUIRE_MESSAGE(r->status == 0, r->err);
  const double h = plain.json()["h"], t = plain.json()["t"];
  // Default: the centroids diffuse for the cells' time (4h^2).
  CHECK(t == doctest::Approx(4 * h * h).epsilon(1e-12));
  CHECK(plain.json()["t_centroid"] == t);
  CHECK(h2.json()["t_centroid"].get<double>() == doctest::Approx(2 * h * h).epsilon(1e-12));
  CHECK(abs.json()["t_centroid"].get<double>() == doctest::Approx(0.01).epsilon(1e-12));
  CHECK(h2.json()["t"] == t);
  // The alias is the same run, with a note; a centroid time of its own moves the sites.
  CHECK(alias.err.find("deprecated") != std::string::npos);
  CHECK(h2.err.find("deprecated") == std::string::npos);
  CHECK(alias.json()["t_centroid"] == h2.json()["t_centroid"]);
  CHECK(alias.json()["energy"] == h2.json()["energy"]);
  CHECK(h2.json()["energy"] != plain.json()["energy"]);
  // Both spellings, a bad time, a negative alias: usage errors.
  CHECK(cvt({"--centroid-t", "2h2", "--t-centroid", "2"}).status == 2);
  CHECK(cvt({"--centroid-t", "abc"}).status == 2);
  CHECK(cvt({"--centroid-t", "0"}).status == 2);
  CHECK(cvt({"--t-centroid", "-1"}).status == 2);
}
