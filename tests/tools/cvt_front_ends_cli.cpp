// One orchestration: `locus cvt`, locus::Session::cvt (the command, and the
// cached tier with remesh), the C API (locus_cvt_run) give bit-identical
// remesh vertices and faces, labels and sites on armadillo (Python:
// tests/python/test_front_ends.py). The CLI's are read back from the PLY
// files it writes (binary doubles, exact). The computation itself is checked
// against independent oracles in tests/pipelines/voronoi.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "locus/engine/cvt_request.hpp"
#include "locus/locus.h"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tests/tools/cli_support.hpp"

namespace {

using namespace locus::test_cli;

const std::string kArmadillo = LOCUS_MESH_CACHE_DIR "/armadillo.off";

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

std::vector<double> positions(const locus::Mesh& m) {
  std::vector<double> xyz;
  for (int32_t v = 0; v < m.num_vertices(); ++v) xyz.insert(xyz.end(), {m.x[v], m.y[v], m.z[v]});
  return xyz;
}

std::vector<int32_t> faces(const locus::Mesh& m) { return {m.face_vertices.begin(), m.face_vertices.end()}; }

std::vector<double> as_doubles(const std::vector<int32_t>& v) { return {v.begin(), v.end()}; }

}  // namespace

TEST_CASE("cvt: the CLI, the Session (command and cached tier) and the C API agree bit for bit") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-cvt");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  struct Case {
    std::vector<std::string> args;
    locus::CvtRequest q;
  };
  locus::CvtRequest options;  // options away from their defaults
  options.t = "2h2";
  options.centroid_t = "3h2";
  options.fit_rings = 1;
  options.fit_sigma = 0;
  options.optimize = 2;
  options.no_split = true;
  for (Case k : {Case{{}, {}}, Case{{"--t", "2h2", "--centroid-t", "3h2", "--fit-rings", "1", "--fit-sigma", "0",
                                     "--optimize", "2", "--no-split"},
                                    options}}) {
    CAPTURE(k.args.size());
    k.q.sites = 150;
    k.q.iters = 3;
    k.q.seed = 5;
    std::vector<std::string> args = {"cvt",     kArmadillo,          "--sites",  "150",  "--iters",
                                     "3",       "--seed",            "5",        "--threads", "2",
                                     "-o",      dir / "r.ply",       "--labels", dir / "l.ply",
                                     "--sites-out", dir / "s.ply",   "--json"};
    args.insert(args.end(), k.args.begin(), k.args.end());
    const Run run = run_locus(dir, args);
    REQUIRE_MESSAGE(run.status == 0, run.err);
    const nlohmann::json j = nlohmann::json::parse(run.out);
    const locus::Mesh cli_remesh = locus::read_mesh(dir / "r.ply");
    const std::vector<double> cli_labels = vertex_property(dir / "l.ply", "label");
    const std::vector<double> cli_sites = positions(locus::read_mesh(dir / "s.ply"));

    const locus::CvtReport r = s.cvt(k.q);
    REQUIRE(r.complete);
    CHECK(same_bits(positions(r.remesh), positions(cli_remesh)));
    CHECK(faces(r.remesh) == faces(cli_remesh));
    CHECK(same_bits(as_doubles(r.label), cli_labels));
    CHECK(same_bits(r.site_xyz, cli_sites));
    CHECK(j["remesh"]["vertices"] == r.remesh_stats.vertices);
    CHECK(j["remesh"]["hausdorff_rel"].get<double>() == r.remesh_stats.hausdorff_rel);
    CHECK(j["energy"].get<std::vector<double>>() == r.energy);

    locus_cvt_options o = locus_cvt_options_default();
    o.sites = 150, o.iters = 3, o.seed = 5;
    o.t = k.q.t.c_str(), o.centroid_t = k.q.centroid_t.c_str();
    o.fit_rings = k.q.fit_rings, o.fit_sigma = k.q.fit_sigma, o.optimize = k.q.optimize, o.no_split = k.q.no_split;
    std::vector<int32_t> labels(static_cast<size_t>(s.num_vertices()));
    locus_cvt_report rep;
    locus_remesh* h = nullptr;
    REQUIRE(locus_cvt_run(c, &o, labels.data(), &rep, &h, nullptr) == LOCUS_OK);
    CHECK(labels == r.label);
    REQUIRE(rep.remesh.vertices == r.remesh_stats.vertices);
    std::vector<double> xyz(3 * static_cast<size_t>(rep.remesh.vertices));
    std::vector<int32_t> tris(3 * static_cast<size_t>(rep.remesh.faces));
    REQUIRE(locus_remesh_get(h, xyz.data(), tris.data()) == LOCUS_OK);
    CHECK(same_bits(xyz, positions(r.remesh)));
    CHECK(tris == faces(r.remesh));
    REQUIRE(locus_remesh_num_sites(h) == rep.sites);
    std::vector<double> sites(3 * static_cast<size_t>(rep.sites));
    REQUIRE(locus_remesh_get_sites(h, sites.data()) == LOCUS_OK);
    CHECK(same_bits(sites, r.site_xyz));
    CHECK(rep.complete == 1);
    CHECK(rep.remesh.hausdorff_rel == r.remesh_stats.hausdorff_rel);
    locus_remesh_destroy(h);
  }
  // The cached tier (the Session's kept operator) runs the same sequence: the same remesh.
  locus::CvtRequest q;
  q.sites = 150, q.iters = 3, q.seed = 5;
  const locus::CvtReport r = s.cvt(q);
  const locus::CvtResult tier = s.cvt(150, 3, 5, {}, true);
  CHECK(same_bits(tier.remesh_xyz, positions(r.remesh)));
  CHECK(tier.remesh_triangles == faces(r.remesh));
  CHECK(same_bits(tier.site_xyz, r.site_xyz));
  // Refusals: the engine's checks, one status everywhere.
  locus_cvt_options bad = locus_cvt_options_default();
  bad.solver = "exact";
  CHECK(locus_cvt_run(c, &bad, nullptr, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  bad = locus_cvt_options_default();
  bad.labels = "labels.txt";
  CHECK(locus_cvt_run(c, &bad, nullptr, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  bad = locus_cvt_options_default();
  bad.sites = 100000000;  // its subdivision beyond 32-bit indices on this mesh: bad input, as the CLI's exit 3
  CHECK(locus_cvt_run(c, &bad, nullptr, nullptr, nullptr, nullptr) == LOCUS_BAD_INPUT);
  bad = locus_cvt_options_default();
  bad.anisotropy = 0.05;
  bad.save = "f.locus";
  CHECK(locus_cvt_run(c, &bad, nullptr, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  locus_session_destroy(c);
}

TEST_CASE("cvt --features: the CLI, the Session and the C API agree bit for bit and count the same features") {
  const std::string fandisk = LOCUS_MESH_CACHE_DIR "/fandisk.off";
  if (!have_locus() || !std::filesystem::exists(fandisk)) return;
  Scratch dir("front-ends-cvt-features");
  const Run run = run_locus(dir, {"cvt", fandisk, "--sites", "300", "--iters", "3", "--features", "30", "--threads",
                                  "2", "-o", dir / "r.ply", "--json"});
  REQUIRE_MESSAGE(run.status == 0, run.err);
  const nlohmann::json f = nlohmann::json::parse(run.out)["remesh"]["features"];
  const locus::Mesh cli_remesh = locus::read_mesh(dir / "r.ply");
  const locus::Session s = locus::Session::from_file(fandisk);
  locus::CvtRequest q;
  q.sites = 300, q.iters = 3, q.features = 30;
  const locus::CvtReport r = s.cvt(q);
  REQUIRE(r.complete);
  CHECK(same_bits(positions(r.remesh), positions(cli_remesh)));
  CHECK(faces(r.remesh) == faces(cli_remesh));
  CHECK(f["edges"] == r.feature_edges);
  CHECK(f["curves"] == r.feature_curves);
  CHECK(f["corners"] == r.feature_corners);
  CHECK(f["sites"] == r.feature_sites);
  CHECK(r.feature_corners > 0);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(fandisk.c_str(), &c) == LOCUS_OK);
  locus_cvt_options o = locus_cvt_options_default();
  CHECK(o.features == 0);
  o.sites = 300, o.iters = 3, o.features = 30;
  locus_cvt_report rep;
  locus_remesh* h = nullptr;
  REQUIRE(locus_cvt_run(c, &o, nullptr, &rep, &h, nullptr) == LOCUS_OK);
  std::vector<double> xyz(3 * static_cast<size_t>(rep.remesh.vertices));
  std::vector<int32_t> tris(3 * static_cast<size_t>(rep.remesh.faces));
  REQUIRE(locus_remesh_get(h, xyz.data(), tris.data()) == LOCUS_OK);
  CHECK(same_bits(xyz, positions(r.remesh)));
  CHECK(tris == faces(r.remesh));
  CHECK(rep.feature_edges == r.feature_edges);
  CHECK(rep.feature_curves == r.feature_curves);
  CHECK(rep.feature_corners == r.feature_corners);
  CHECK(rep.feature_sites == r.feature_sites);
  locus_remesh_destroy(h);
  for (double bad : {-1.0, 180.0, std::nan("")}) {
    o.features = bad;
    CHECK(locus_cvt_run(c, &o, nullptr, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  }
  locus_session_destroy(c);
}
