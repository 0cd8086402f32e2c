// One orchestration: `locus deform` and `locus param`, locus::Session (the
// commands, and the older DeformRequest call) and the C API give
// bit-identical positions and uv on armadillo and a quad grid. The CLI's are
// read back from the PLY it writes (binary doubles, exact). The computations
// themselves are checked against independent oracles in tests/pipelines.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <sstream>
#include <filesystem>
#include <string>
#include <vector>

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

std::vector<double> positions(const std::string& path) {
  const locus::Mesh m = locus::read_mesh(path);
  std::vector<double> xyz;
  for (int32_t v = 0; v < m.num_vertices(); ++v) xyz.insert(xyz.end(), {m.x[v], m.y[v], m.z[v]});
  return xyz;
}

}  // namespace

TEST_CASE("deform: the CLI, the Session and the C API agree bit for bit (laplacian and bilaplacian)") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-deform");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  for (const std::string energy : {"laplacian", "bilaplacian"}) {
    CAPTURE(energy);
    const std::string out = dir / ("d-" + energy + ".ply");
    const Run r = run_locus(dir, {"deform", kArmadillo, "--roi-seed", "0", "--roi-fraction", "0.1", "--handle", "0",
                                  "--offset", "0.01,0.02,0", "--energy", energy, "--threads", "2", "-o", out});
    REQUIRE(r.status == 0);
    locus::DeformCommandRequest q;
    q.roi_seed = 0;
    q.handle = 0;
    q.offset = {0.01, 0.02, 0};
    q.energy = energy;
    const locus::DeformCommandReport session = s.deform(q);
    CHECK(same_bits(positions(out), session.xyz));
    CHECK(session.max_displacement > 0);
    locus::DeformRequest old;  // the older call: the same computation
    old.roi_seed = 0;
    old.handle_vertex = 0;
    old.offset = q.offset;
    old.energy = energy == "bilaplacian" ? locus::DeformEnergyKind::Bilaplacian : locus::DeformEnergyKind::Laplacian;
    CHECK(same_bits(s.deform(old).xyz, session.xyz));
    locus_deform_options o = locus_deform_options_default();
    o.roi_seed = 0;
    o.handle = 0;
    o.offset[0] = 0.01, o.offset[1] = 0.02, o.offset[2] = 0;
    o.energy = energy.c_str();
    std::vector<double> capi(session.xyz.size());
    locus_deform_report rep;
    REQUIRE(locus_deform_run(c, &o, capi.data(), &rep, nullptr) == LOCUS_OK);
    CHECK(same_bits(capi, session.xyz));
    CHECK(rep.free_vertices == session.free_vertices);
  }
  // Another regularization factors its own global operator: still the CLI's numbers.
  const std::string out = dir / "d-reg.ply";
  REQUIRE(run_locus(dir, {"deform", kArmadillo, "--roi-seed", "5", "--handle", "5", "--offset", "0,0,0.01",
                          "--regularization", "1e-4", "-o", out})
              .status == 0);
  locus::DeformCommandRequest q;
  q.roi_seed = 5;
  q.handle = 5;
  q.offset = {0, 0, 0.01};
  q.regularization = 1e-4;
  CHECK(same_bits(positions(out), s.deform(q).xyz));
  // Refusals: the engine's checks, one status everywhere.
  locus_deform_options bad = locus_deform_options_default();  // roi_seed and handle not given
  std::vector<double> xyz(3 * static_cast<size_t>(s.num_vertices()));
  CHECK(locus_deform_run(c, &bad, xyz.data(), nullptr, nullptr) == LOCUS_BAD_USAGE);
  bad.roi_seed = bad.handle = 0;
  bad.regularization = 0;
  CHECK(locus_deform_run(c, &bad, xyz.data(), nullptr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(run_locus(dir, {"deform", "no-such.off", "--roi-seed", "0", "--handle", "0", "--offset", "0,0,0",
                        "--energy", "elastic"})
            .status == 2);
  CHECK(run_locus(dir, {"deform", kArmadillo, "--roi-seed", "99999999", "--handle", "0", "--offset", "0,0,0"})
            .status == 3);
  locus_session_destroy(c);
}

namespace {

// A 9x9-vertex quad grid with a bump: a polygon disk.
std::string quad_grid() {
  const int n = 9;
  std::ostringstream o;
  o << "OFF\n" << n * n << " " << (n - 1) * (n - 1) << " 0\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i / double(n - 1) - 0.5, y = j / double(n - 1) - 0.5;
      o << x << " " << y << " " << 0.2 * std::exp(-8 * (x * x + y * y)) << "\n";
    }
  for (int j = 0; j < n - 1; ++j)
    for (int i = 0; i < n - 1; ++i) {
      const int v = j * n + i;
      o << "4 " << v << " " << v + 1 << " " << v + n + 1 << " " << v + n << "\n";
    }
  return o.str();
}

// The (u, v) of a PLY the CLI wrote, interleaved.
std::vector<double> uv_of(const std::string& path) {
  const std::vector<double> u = vertex_property(path, "u"), v = vertex_property(path, "v");
  std::vector<double> uv;
  for (size_t k = 0; k < u.size(); ++k) uv.insert(uv.end(), {u[k], v[k]});
  return uv;
}

}  // namespace

TEST_CASE("param: the CLI, the Session and the C API agree bit for bit (disk on polygons, patches)") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-param");
  const std::string grid = dir / "grid.off";
  write_text(grid, quad_grid());
  const locus::Session g = locus::Session::from_file(grid);
  for (const std::string method : {"perfect", "uniform"}) {  // cotan needs triangles
    CAPTURE(method);
    const std::string out = dir / ("disk-" + method + ".ply");
    REQUIRE(run_locus(dir, {"param", grid, "--method", method, "-o", out}).status == 0);
    locus::ParamRequest q;
    q.method = method;
    const locus::ParamReport r = g.param(q);
    CHECK(same_bits(uv_of(out), r.uv));
  }
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  for (const std::string boundary : {"neumann", "circle"}) {
    CAPTURE(boundary);
    const std::string out = dir / ("patch-" + boundary + ".ply");
    REQUIRE(run_locus(dir, {"param", kArmadillo, "--center", "0", "--fraction", "0.1", "--boundary", boundary, "-o",
                            out})
                .status == 0);
    locus::ParamRequest q;
    q.center = 0;
    q.boundary = boundary;
    const locus::ParamReport r = s.param(q);
    CHECK(same_bits(uv_of(out), r.uv));
    locus_param_options o = locus_param_options_default();
    o.center = 0;
    o.boundary = boundary.c_str();
    std::vector<double> uv(2 * static_cast<size_t>(s.num_vertices()));
    locus_param_report rep;
    REQUIRE(locus_param_run(c, &o, uv.data(), &rep, nullptr) == LOCUS_OK);
    std::vector<double> patch_uv;
    for (int32_t v : r.patch_vertices) patch_uv.insert(patch_uv.end(), {uv[2 * size_t(v)], uv[2 * size_t(v) + 1]});
    CHECK(same_bits(patch_uv, r.uv));
    CHECK(rep.patch_size == static_cast<int64_t>(r.patch_vertices.size()));
    CHECK(rep.flipped_faces == r.flipped_faces);
  }
  locus_param_options bad = locus_param_options_default();
  bad.boundary = "circle";  // the disk has no boundary choice
  std::vector<double> uv(2 * static_cast<size_t>(s.num_vertices()));
  CHECK(locus_param_run(c, &bad, uv.data(), nullptr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(run_locus(dir, {"param", "no-such.off", "--center", "0", "--boundary", "square"}).status == 2);
  locus_session_destroy(c);
}
