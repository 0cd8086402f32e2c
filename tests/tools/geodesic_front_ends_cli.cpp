// One orchestration: `locus geodesic` / `locus logmap`, locus::Session and
// the C API give bit-identical answers on armadillo (whole-mesh and localized
// geodesic distance, the localized and the DEM log map). The CLI's values are
// read back from the PLY it writes (doubles, exact); Python's are checked
// against the same files in tests/python/test_front_ends.py.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "locus/locus.h"
#include "locus/session.hpp"
#include "tests/tools/cli_support.hpp"

namespace {

using namespace locus::test_cli;

const std::string kArmadillo = LOCUS_MESH_CACHE_DIR "/armadillo.off";

// Equal bit for bit, NaN (no value) equal to NaN.
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) && std::isnan(b[i])) continue;
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0) return false;
  }
  return true;
}

std::vector<double> per_vertex(size_t n, const std::vector<int32_t>& patch, const std::vector<double>& values) {
  std::vector<double> out(n, std::nan(""));
  for (size_t k = 0; k < patch.size(); ++k) out[static_cast<size_t>(patch[k])] = values[k];
  return out;
}

}  // namespace

TEST_CASE("geodesic: the CLI, the Session and the C API agree bit for bit (whole mesh and --fraction)") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-geodesic");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  struct Case {
    int64_t source;
    double fraction;
    std::string fraction_text;
  };
  for (const Case& k : {Case{0, 1.0, "1"}, Case{100, 0.1, "0.1"}}) {
    CAPTURE(k.source);
    const std::string out = dir / ("g" + std::to_string(k.source) + ".ply");
    const Run r = run_locus(dir, {"geodesic", kArmadillo, "--source", std::to_string(k.source), "--fraction",
                                  k.fraction_text, "--threads", "2", "-o", out});
    REQUIRE(r.status == 0);
    const std::vector<double> cli = vertex_property(out, "distance");
    locus::GeodesicRequest q;
    q.source = k.source;
    q.fraction = k.fraction;
    const locus::GeodesicReport session = s.geodesic(q);
    CHECK(same_bits(cli, session.distance));
    CHECK(same_bits(vertex_property(out, "valid"), session.valid));
    locus_geodesic_options o = locus_geodesic_options_default();
    o.source = k.source;
    o.fraction = k.fraction;
    std::vector<double> capi(static_cast<size_t>(s.num_vertices()));
    locus_geodesic_report rep;
    REQUIRE(locus_geodesic_run(c, &o, capi.data(), &rep, nullptr) == LOCUS_OK);
    CHECK(same_bits(capi, session.distance));
    CHECK(rep.patch_size == session.patch_size);
    if (k.fraction == 1.0) {  // the older call is a thin wrapper of the same computation
      std::vector<double> old(capi.size());
      REQUIRE(locus_geodesic_distance(c, k.source, old.data()) == LOCUS_OK);
      CHECK(same_bits(old, capi));
    }
  }
  locus_session_destroy(c);
}

TEST_CASE("logmap: the CLI, the Session and the C API agree bit for bit (heat and dem)") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-logmap");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  const size_t n = static_cast<size_t>(s.num_vertices());
  for (const std::string method : {"heat", "dem"}) {
    CAPTURE(method);
    const std::string out = dir / ("m-" + method + ".ply");
    const Run r = run_locus(dir, {"logmap", kArmadillo, "--center", "0", "--fraction", "0.06", "--method", method,
                                  "--threads", "2", "-o", out});
    REQUIRE(r.status == 0);
    locus::LogmapRequest q;
    q.center = 0;
    q.fraction = 0.06;
    q.method = method;
    const locus::LogmapReport session = s.logmap(q);
    const std::vector<int32_t> patch(session.patch.begin(), session.patch.end());
    CHECK(same_bits(vertex_property(out, "distance"), per_vertex(n, patch, session.distance)));
    CHECK(same_bits(vertex_property(out, "angle"), per_vertex(n, patch, session.angle)));
    locus_logmap_options o = locus_logmap_options_default();
    o.center = 0;
    o.fraction = 0.06;
    o.method = method.c_str();
    std::vector<double> uv(2 * n), dist(n), ang(n);
    locus_logmap_report rep;
    REQUIRE(locus_logmap_run(c, &o, uv.data(), dist.data(), ang.data(), &rep, nullptr) == LOCUS_OK);
    CHECK(same_bits(dist, per_vertex(n, patch, session.distance)));
    CHECK(same_bits(ang, per_vertex(n, patch, session.angle)));
    std::vector<double> u(n), v(n);
    for (size_t i = 0; i < n; ++i) u[i] = uv[2 * i], v[i] = uv[2 * i + 1];
    CHECK(same_bits(u, per_vertex(n, patch, session.u)));
    CHECK(same_bits(v, per_vertex(n, patch, session.v)));
    CHECK(rep.patch_size == static_cast<int64_t>(session.patch.size()));
    CHECK(rep.flipped == session.flipped);
  }
  locus_session_destroy(c);
}
