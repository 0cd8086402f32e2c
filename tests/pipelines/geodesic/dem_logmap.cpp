// Tests for pipelines/dem_logmap (discrete exponential map baseline, thesis
// §6.7; Schmidt et al. 2006). Oracles: the plane, where DEM is exact by
// construction (every frame is the center's, every log_r(q) is q - r); a
// from-scratch Dijkstra (std::priority_queue, lazy deletion) for the disk's
// vertex set and order; great-circle distance and azimuth on a unit icosphere.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <queue>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"

using namespace locus;

namespace {

double wrap(double a) { return std::remainder(a, 2 * std::numbers::pi); }

std::vector<double> dijkstra(const Mesh& m, int32_t s) {
  const Adjacency adj = vertex_adjacency(m);
  std::vector<double> d(m.num_vertices(), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  d[s] = 0;
  q.push({0, s});
  while (!q.empty()) {
    const auto [dv, v] = q.top();
    q.pop();
    if (dv > d[v]) continue;
    for (int64_t k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k) {
      const int32_t w = adj.neighbors[k];
      const double nd = dv + std::hypot(m.x[w] - m.x[v], m.y[w] - m.y[v], m.z[w] - m.z[v]);
      if (nd < d[w]) {
        d[w] = nd;
        q.push({nd, w});
      }
    }
  }
  return d;
}

}  // namespace

TEST_CASE("DEM: the patch grower's geodesic disk is the DEM's disk, vertex for vertex (ties included)") {
  // Regular meshes have many equal distances: the order of ties is the heap's,
  // which the grower reproduces operation for operation.
  for (const Mesh& m : {make_grid(20), make_icosphere(3), make_disk(12), make_random_sphere(2000, 8)}) {
    const DemLogMap dem(m);
    const PatchGrower g = prepare_patch_grower(m);
    DemWorkspace dws;
    PatchWorkspace pws;
    const int32_t n = m.num_vertices();
    std::vector<int32_t> want(n), got;
    for (int32_t c : {0, n / 3, n - 1})
      for (int32_t count : {1, 9, n / 7, n / 2, n}) {
        CAPTURE(n);
        CAPTURE(c);
        CAPTURE(count);
        want.resize(n);
        want.resize(dem.query(c, count, std::numeric_limits<double>::infinity(), want, {}, {}, dws));
        grow_patch_vertices(g, c, geodesic_disk(count), pws, got);
        CHECK(got == want);
      }
  }
}

TEST_CASE("DEM: exact polar coordinates on a plane (up to the reference rotation)") {
  Mesh m = make_disk(30, 0.3, 9);  // flipped diagonals: irregular, still planar
  for (double& z : m.z) z = 0;
  // Tilt the plane so the frames are not axis-aligned.
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    const double y = m.y[i];
    m.y[i] = 0.6 * y;
    m.z[i] = 0.8 * y;
  }
  const DemLogMap dem(m);
  DemWorkspace ws;
  const int32_t n = m.num_vertices(), c = 0;
  std::vector<int32_t> patch(n);
  std::vector<double> u(n), v(n);
  const int32_t k = dem.query(c, n / 2, std::numeric_limits<double>::infinity(), patch, u, v, ws);
  CHECK(k == n / 2);
  CHECK(patch[0] == c);
  // In-plane orthonormal coordinates: (x, (0.6 y' + 0.8 z')) recovers the disk.
  double rot = 0;
  for (int32_t p = 1; p < k; ++p) {
    const int32_t j = patch[p];
    const double px = m.x[j] - m.x[c], py = 0.6 * (m.y[j] - m.y[c]) + 0.8 * (m.z[j] - m.z[c]);
    CHECK(std::abs(std::hypot(u[p], v[p]) - std::hypot(px, py)) < 1e-12);
    const double diff = wrap(std::atan2(v[p], u[p]) - std::atan2(py, px));
    if (p == 1) rot = diff;
    CHECK(std::abs(wrap(diff - rot)) < 1e-10);
  }
}

TEST_CASE("DEM: the disk is the Dijkstra disk, in order") {
  const Mesh m = make_random_sphere(3000, 4);
  const DemLogMap dem(m);
  DemWorkspace ws;
  const int32_t c = 1234, count = 400;
  const std::vector<double> d = dijkstra(m, c);
  std::vector<int32_t> patch(count);
  for (int rep = 0; rep < 2; ++rep) {  // the workspace is clean for the second query
    const int32_t k = dem.query(c, count, std::numeric_limits<double>::infinity(), patch, {}, {}, ws);
    REQUIRE(k == count);
    for (int32_t p = 1; p < k; ++p) CHECK(d[patch[p - 1]] <= d[patch[p]]);
    std::vector<double> sorted = d;
    std::sort(sorted.begin(), sorted.end());
    CHECK(d[patch[k - 1]] == sorted[count - 1]);
  }
  // Radius limit.
  const int32_t k = dem.query(c, m.num_vertices(), 0.2, patch = std::vector<int32_t>(m.num_vertices()), {}, {}, ws);
  int32_t inside = 0;
  for (double x : d) inside += x <= 0.2;
  CHECK(k == inside);
}

TEST_CASE("DEM: unit icosphere, distance and azimuth close to exact") {
  const Mesh m = make_icosphere(5);
  const DemLogMap dem(m);
  DemWorkspace ws;
  const int32_t n = m.num_vertices(), c = 333;
  std::vector<int32_t> patch(n);
  std::vector<double> u(n), v(n);
  const int32_t k = dem.query(c, n, 0.5, patch, u, v, ws);
  double b1[3] = {1, 0, 0};
  const double nn[3] = {m.x[c], m.y[c], m.z[c]};
  const double t = b1[0] * nn[0];
  for (int q = 0; q < 3; ++q) b1[q] -= t * nn[q];
  const double l = std::sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
  for (double& x : b1) x /= l;
  const double b2[3] = {nn[1] * b1[2] - nn[2] * b1[1], nn[2] * b1[0] - nn[0] * b1[2], nn[0] * b1[1] - nn[1] * b1[0]};
  std::vector<double> diff(k);
  double ed = 0, cs = 0, sn = 0;
  for (int32_t p = 1; p < k; ++p) {
    const int32_t j = patch[p];
    const double exact_d = std::acos(std::clamp(m.x[c] * m.x[j] + m.y[c] * m.y[j] + m.z[c] * m.z[j], -1.0, 1.0));
    const double exact_a = std::atan2(m.x[j] * b2[0] + m.y[j] * b2[1] + m.z[j] * b2[2],
                                      m.x[j] * b1[0] + m.y[j] * b1[1] + m.z[j] * b1[2]);
    ed += std::abs(std::hypot(u[p], v[p]) - exact_d) / (k - 1);
    diff[p] = std::atan2(v[p], u[p]) - exact_a;
    cs += std::cos(diff[p]);
    sn += std::sin(diff[p]);
  }
  double ea = 0;
  for (int32_t p = 1; p < k; ++p) ea += std::abs(wrap(diff[p] - std::atan2(sn, cs))) / (k - 1);
  MESSAGE("DEM icosphere 5: E_d " << ed << ", E_a " << ea);
  CHECK(ed < 2e-3);  // measured ~3e-4
  CHECK(ea < 8e-3);  // measured ~3e-3
}

TEST_CASE("DEM: bad queries") {
  const Mesh m = make_icosphere(2);
  const DemLogMap dem(m);
  DemWorkspace ws;
  std::vector<int32_t> patch(10);
  std::vector<double> u(10), v(10), shortv(3);
  auto code = [&](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::Internal;
  };
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(code([&] { dem.query(-1, 5, inf, patch, u, v, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { dem.query(m.num_vertices(), 5, inf, patch, u, v, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { dem.query(0, 0, inf, patch, u, v, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { dem.query(0, 11, inf, patch, u, v, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { dem.query(0, 5, inf, patch, u, shortv, ws); }) == ErrorCode::BadUsage);
  Mesh quad;
  for (int i = 0; i < 4; ++i) quad.add_vertex(i & 1, i >> 1, 0);
  const int32_t q[4] = {0, 1, 3, 2};
  quad.add_face(q);
  CHECK(code([&] { DemLogMap bad(quad); }) == ErrorCode::BadInput);
}
