// What the heat method refuses (pipelines/src/geodesic/heat_geodesic_limits.hpp):
// a diffusion time beyond 1e6 h^2 (at 1e300 h^2 most distances came
// out negative), both factors and the per-mesh data beyond the memory limit;
// and on meshes at the ends of the size range (coordinate_range.hpp) the heat's
// magnitude no longer underflows. Oracles: the unit icosphere's own distances,
// scaled, and the sign of a distance.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"

using namespace locus;

namespace {

Mesh scaled(Mesh m, double s) {
  for (auto* c : {&m.x, &m.y, &m.z})
    for (double& v : *c) v *= s;
  return m;
}

std::vector<double> distances(const Mesh& m, const HeatGeodesicOptions& opt, HeatGeodesicWorkspace& ws) {
  const HeatGeodesic g(m, opt);
  std::vector<double> d(static_cast<size_t>(m.num_vertices()));
  g.query_full(0, d, ws);
  return d;
}

}  // namespace

TEST_CASE("heat geodesic limits: a time beyond 1e6 h^2 is refused naming the limit") {
  const Mesh m = make_icosphere(2);
  for (double tf : {1e300, 1e20, 2e6}) {
    CAPTURE(tf);
    HeatGeodesicOptions opt;
    opt.t_factor = tf;
    try {
      HeatGeodesic g(m, opt);
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::BadUsage);
      CHECK(std::string(e.what()).find("at most 1e+06 h^2") != std::string::npos);
    }
  }
  // At the limit every distance is a distance: >= 0, and 0 only at the source.
  HeatGeodesicOptions opt;
  opt.t_factor = 1e6;
  HeatGeodesicWorkspace ws;
  const std::vector<double> d = distances(make_icosphere(3), opt, ws);
  CHECK(d[0] == 0.0);
  for (size_t i = 1; i < d.size(); ++i) CHECK(d[i] > 0);
}

TEST_CASE("heat geodesic limits: at the ends of the size range the distances are the unit sphere's, scaled") {
  const Mesh unit = make_icosphere(3);
  HeatGeodesicWorkspace ws;
  const std::vector<double> d1 = distances(unit, {}, ws);
  CHECK(ws.underflow == 0);
  for (double s : {1e149, 1e-149}) {
    CAPTURE(s);
    const std::vector<double> d = distances(scaled(unit, s), {}, ws);
    CHECK(ws.underflow == 0);  // the heat's magnitude ~1/h^2 no longer underflows at 1e149
    double worst = 0;
    for (size_t i = 1; i < d.size(); ++i) worst = std::max(worst, std::abs(d[i] / s - d1[i]) / d1[i]);
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("heat geodesic limits: both factors and the per-mesh data are held to the memory limit") {
  const Mesh m = make_icosphere(5);  // 10242 vertices: two factors of a few MB each
  RunContext ctx;
  ctx.max_memory_bytes = 4u << 20;
  try {
    HeatGeodesic g(m, {}, ctx);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::ResourceLimit);
    CHECK(std::string(e.what()).find("two factors") != std::string::npos);
  }
  ctx.max_memory_bytes = 256u << 20;
  CHECK_NOTHROW(HeatGeodesic(m, {}, ctx));
}
