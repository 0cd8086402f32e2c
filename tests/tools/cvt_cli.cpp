// `locus cvt MESH` as users run it: the default diffusion time is 4h^2 (h the mean
// edge length, computed here from the mesh), --t h2 selects the thesis's h^2, the
// timing and quality JSON keys are present, and a bad --t exits 2.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
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

TEST_CASE("cvt CLI: default t = 4h^2, --t h2, timing and quality JSON keys, bad --t exits 2") {
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

namespace {

// `locus cvt MESH -o FILE` and the file read back (the project's reader) and by
// `locus info`: a manifold with the input's Euler characteristic, components
// and boundary loops; the JSON `remesh` object says the same.
void check_remesh_cli(const Scratch& dir, const std::string& mesh, const std::string& sites, const std::string& ext) {
  const locus::Mesh in = locus::read_mesh(mesh);
  const locus::MeshReport want = locus::analyze_mesh(in);
  const std::string out = dir / ("remesh." + ext), labels = dir / "labels.ply", pts = dir / "sites.ply",
                    png = dir / "remesh.png";
  const Run r = run_locus(dir, {"cvt", mesh, "--sites", sites, "--iters", "3", "-o", out, "--labels", labels,
                                "--sites-out", pts, "--preview", png, "--json"});
  REQUIRE_MESSAGE(r.status == 0, r.err);
  const auto j = r.json()["remesh"];
  for (const char* k : {"vertices", "faces", "manifold", "genus", "components", "boundary_loops", "mean_min_angle_deg",
                        "min_angle_deg", "pct_below_30_deg", "hausdorff_rel", "added_sites"})
    CHECK_MESSAGE(j.contains(k), k);
  for (const char* k : {"load", "factor", "lloyd", "repair", "dual", "optimize", "write", "total"})
    CHECK_MESSAGE(r.json()["timings"].contains(std::string(k) + "_s"), k);
  const locus::Mesh back = locus::read_mesh(out);
  const locus::MeshReport got = locus::analyze_mesh(back);
  CHECK(got.manifold);
  CHECK(got.unreferenced_vertices == 0);
  CHECK(got.degenerate_faces == 0);
  CHECK(got.euler_characteristic == want.euler_characteristic);
  CHECK(got.components == want.components);
  CHECK(got.boundary_loops == want.boundary_loops);
  CHECK(j["vertices"] == back.num_vertices());
  CHECK(j["faces"] == back.num_faces());
  CHECK(j["manifold"] == true);
  CHECK(j["components"] == want.components);
  CHECK(j["boundary_loops"] == want.boundary_loops);
  CHECK(j["hausdorff_rel"].get<double>() > 0);
  CHECK(j["hausdorff_rel"].get<double>() < 0.05);
  CHECK(j["min_angle_deg"].get<double>() <= j["mean_min_angle_deg"].get<double>());
  const Run info = run_locus(dir, {"info", out, "--json"});
  REQUIRE_MESSAGE(info.status == 0, info.err);
  CHECK(info.json()["manifold"] == true);
  CHECK(info.json()["euler_characteristic"] == want.euler_characteristic);
  CHECK(info.json()["boundary_loops"] == want.boundary_loops);
  CHECK(info.json()["components"] == want.components);
  // Labels on the input, sites as points (the added ones included), the preview.
  const locus::Mesh lab = locus::read_mesh(labels);
  CHECK(lab.num_vertices() == in.num_vertices());
  CHECK(lab.num_faces() == in.num_faces());
  CHECK(locus::read_mesh(pts).num_vertices() == std::stoi(sites) + j["added_sites"].get<int>());
  CHECK(fs::file_size(png) > 1000);
}

}  // namespace

TEST_CASE("cvt CLI: -o writes the manifold remesh (OBJ, PLY, OFF) with the input's topology") {
  if (!have_locus()) return;
  Scratch dir("cvt-remesh-cli");
  const std::string torus = dir / "torus.off";
  locus::write_mesh(torus, locus::make_torus(120, 48));  // genus 1
  check_remesh_cli(dir, torus, "300", "obj");
  check_remesh_cli(dir, torus, "300", "ply");
  if (fs::exists(LOCUS_MESH_CACHE_DIR "/armadillo.off")) check_remesh_cli(dir, LOCUS_MESH_CACHE_DIR "/armadillo.off", "1000", "off");
  // Too few sites for a genus-1 surface: no manifold remesh; -o fails and writes nothing.
  const Run few = run_locus(dir, {"cvt", torus, "--sites", "3", "--repair-rounds", "0", "-o", dir / "few.obj"});
  CHECK(few.status == 4);
  CHECK(few.err.find("closed-ball") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "few.obj"));
}

TEST_CASE("cvt CLI: --features DEG keeps a cube's corners; its JSON counts the features; crowded curves said; bad DEG exits 2") {
  if (!have_locus()) return;
  Scratch dir("cvt-features");
  // The cube [-1, 1]^3 (a cube-sphere's vertices taken back to the cube): 12
  // edges of dihedral angle 90 degrees meeting at 8 corners.
  locus::Mesh m = locus::make_cube_sphere(10, true);
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double s = std::max({std::abs(m.x[v]), std::abs(m.y[v]), std::abs(m.z[v])});
    m.x[v] /= s, m.y[v] /= s, m.z[v] /= s;
  }
  const std::string cube = dir / "cube.off", out = dir / "remesh.off";
  locus::write_mesh(cube, m);
  const Run r = run_locus(dir, {"cvt", cube, "--sites", "120", "--features", "30", "--json", "-o", out});
  REQUIRE_MESSAGE(r.status == 0, r.err);
  const auto f = r.json()["remesh"]["features"];
  CHECK(f["angle_deg"].get<double>() == 30);
  CHECK(f["edges"].get<int>() == 12 * 10);
  CHECK(f["curves"].get<int>() == 12);
  CHECK(f["corners"].get<int>() == 8);
  CHECK(f["sites"].get<int>() >= 8);
  const locus::Mesh back = locus::read_mesh(out);
  int corners = 0;
  for (int32_t v = 0; v < back.num_vertices(); ++v)
    corners += std::abs(back.x[v]) == 1 && std::abs(back.y[v]) == 1 && std::abs(back.z[v]) == 1;
  CHECK(corners == 8);
  // Feature curves that take more than half the sites are said, with the
  // count that leaves room between them: at 30 sites, not at 120.
  const std::string crowded = "the feature curves need ";
  CHECK(r.err.find(crowded) == std::string::npos);
  const Run few = run_locus(dir, {"cvt", cube, "--sites", "30", "--features", "30", "--json"});
  REQUIRE_MESSAGE(few.status == 0, few.err);
  const int fs = few.json()["remesh"]["features"]["sites"].get<int>();
  CHECK(fs > 15);
  CHECK(few.err.find(crowded + std::to_string(fs) + " sites at the spacing of --sites 30") != std::string::npos);
  CHECK(few.err.find("ask for about " + std::to_string(4 * fs) + " sites") != std::string::npos);
  const Run plain = run_locus(dir, {"cvt", cube, "--sites", "120", "--json"});
  REQUIRE_MESSAGE(plain.status == 0, plain.err);
  CHECK_FALSE(plain.json()["remesh"].contains("features"));  // without the option, the JSON of before
  for (const char* bad : {"-1", "180", "nan", "x"}) {
    const Run b = run_locus(dir, {"cvt", cube, "--sites", "20", "--features", bad});
    CHECK_MESSAGE(b.status == 2, bad);
    CHECK_MESSAGE(b.err.find("--features") != std::string::npos, b.err);
  }
}
