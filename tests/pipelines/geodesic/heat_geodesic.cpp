// Tests for pipelines/heat_geodesic (thesis §6.4.1-6.4.2, eqs. 6.3-6.6).
// Oracles: (1) the heat method written out from scratch in the test — Eigen
// sparse Cholesky solves of the two operators, per-triangle gradients from
// cross products (eq. 6.4), and Crane et al.'s cotangent form of the
// divergence — against query_full; (2) analytic distances: great-circle angles
// on unit icospheres (converging with the level) and Euclidean distance on a
// planar disk; (3) the localized query against the full one (the Poisson
// right-hand side is the only approximation, measured for both variants).
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"

using namespace locus;

namespace {

using SpMat = Eigen::SparseMatrix<double>;

SpMat to_eigen(const CscMatrix& L) {  // lower-stored symmetric -> full Eigen matrix
  std::vector<Eigen::Triplet<double>> t;
  for (int32_t j = 0; j < L.ncols; ++j)
    for (int64_t q = L.colptr[j]; q < L.colptr[j + 1]; ++q) {
      t.emplace_back(L.rowind[q], j, L.values[q]);
      if (L.rowind[q] != j) t.emplace_back(j, L.rowind[q], L.values[q]);
    }
  SpMat A(L.nrows, L.ncols);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

struct V3 {
  double x, y, z;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(V3 a) { return std::sqrt(dot(a, a)); }

// Crane et al.'s heat method from scratch: heat by Eigen, gradient by eq. 6.4,
// divergence by the cotangent formula (div X)_i = 1/2 sum cot(t1) e1.X + cot(t2) e2.X.
std::vector<double> reference_distance(const Mesh& m, int32_t source, double t, bool log_gradient) {
  const int32_t n = m.num_vertices();
  Eigen::SimplicialLDLT<SpMat> heat(to_eigen(heat_operator(m, t)));
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
  e[source] = 1;
  const Eigen::VectorXd h = heat.solve(e);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  auto P = [&](int32_t v) { return V3{m.x[v], m.y[v], m.z[v]}; };
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const V3 N = cross(P(v[1]) - P(v[0]), P(v[2]) - P(v[0]));
    const double A2 = norm(N);
    const V3 nn = (1.0 / A2) * N;
    V3 g{0, 0, 0};
    for (int s = 0; s < 3; ++s) {
      const double u = log_gradient ? std::log(h[v[s]]) : h[v[s]];
      g = g + (u / A2) * cross(nn, P(v[(s + 2) % 3]) - P(v[(s + 1) % 3]));
    }
    const V3 X = (-1.0 / norm(g)) * g;
    for (int s = 0; s < 3; ++s) {
      const V3 pi = P(v[s]), pj = P(v[(s + 1) % 3]), pk = P(v[(s + 2) % 3]);
      // Angles at the other two corners, opposite the edges from v[s].
      const V3 e1 = pj - pi, e2 = pk - pi;
      const double cot_k = dot(pi - pk, pj - pk) / norm(cross(pi - pk, pj - pk));  // opposite e1
      const double cot_j = dot(pi - pj, pk - pj) / norm(cross(pi - pj, pk - pj));  // opposite e2
      b[v[s]] += 0.5 * (cot_k * dot(e1, X) + cot_j * dot(e2, X));
    }
  }
  // Crane: L_C d = div X, solved exactly: -L_C with d(source) pinned to 0 (the
  // row and column of the source replaced by the identity), no regularization.
  SpMat A = to_eigen(regularized_laplacian(m, 1e-300));  // eps ~ 1e-300: -L_C itself
  for (int k = 0; k < A.outerSize(); ++k)
    for (SpMat::InnerIterator it(A, k); it; ++it)
      if (it.row() == source || it.col() == source) it.valueRef() = it.row() == it.col() ? 1.0 : 0.0;
  Eigen::VectorXd rhs = -b;
  rhs[source] = 0;
  Eigen::SimplicialLDLT<SpMat> poisson(A);
  const Eigen::VectorXd d = poisson.solve(rhs);
  std::vector<double> out(n);
  for (int32_t i = 0; i < n; ++i) out[i] = d[i] - d[source];
  return out;
}

double great_circle(const Mesh& m, int32_t a, int32_t b) {
  const double c = m.x[a] * m.x[b] + m.y[a] * m.y[b] + m.z[a] * m.z[b];
  return std::acos(std::clamp(c, -1.0, 1.0));
}

// Mean |d - exact| over the vertices within geodesic radius r of the source.
double mean_sphere_error(const Mesh& m, int32_t s, const std::vector<double>& d, double r) {
  double e = 0;
  int cnt = 0;
  for (int32_t j = 0; j < m.num_vertices(); ++j)
    if (great_circle(m, s, j) <= r) {
      e += std::abs(d[j] - great_circle(m, s, j));
      ++cnt;
    }
  return e / cnt;
}

std::vector<int32_t> sphere_disk(const Mesh& m, int32_t c, double r) {
  std::vector<int32_t> p{c};
  for (int32_t j = 0; j < m.num_vertices(); ++j)
    if (j != c && great_circle(m, c, j) <= r) p.push_back(j);
  return p;
}

}  // namespace

TEST_CASE("heat geodesic: whole-mesh query equals the heat method written from scratch") {
  const Mesh m = make_random_sphere(600, 3);  // irregular: exercises every triangle shape
  for (bool log_gradient : {false, true}) {
    HeatGeodesicOptions o;
    o.log_heat_gradient = log_gradient;
    const HeatGeodesic geo(m, o);
    HeatGeodesicWorkspace ws;
    for (int32_t s : {0, 77, 599}) {
      std::vector<double> d(m.num_vertices());
      geo.query_full(s, d, ws);
      const std::vector<double> ref = reference_distance(m, s, geo.time(), log_gradient);
      double worst = 0;
      for (size_t i = 0; i < d.size(); ++i) worst = std::max(worst, std::abs(d[i] - ref[i]));
      CHECK(d[s] == 0.0);
      // The regularization eps M of the Poisson operator shrinks the distance by
      // about eps / lambda_1 ~ 1.4e-6 here (HeatGeodesicOptions::poisson_rel);
      // the former eps, 1e-6 trace(-L_C) / trace(M), shrank it by ~1e-4 (2.6e-4 at the antipode).
      CHECK(worst < 1e-5);
    }
  }
}

TEST_CASE("heat geodesic: great-circle distance on unit icospheres, converging with the level") {
  // Patch of radius 1 (about a quarter of the sphere's radius span); distances
  // from the whole-mesh query. Measured: level 4 ~6e-3, level 5 ~3e-3.
  double previous = 1;
  for (int level : {4, 5}) {
    const Mesh m = make_icosphere(level);
    const HeatGeodesic geo(m);
    HeatGeodesicWorkspace ws;
    std::vector<double> d(m.num_vertices());
    geo.query_full(17, d, ws);
    const double e = mean_sphere_error(m, 17, d, 1.0);
    MESSAGE("icosphere level " << level << ": mean |d - exact| = " << e);
    CHECK(e < 0.6 * previous);
    CHECK(e < 0.012);
    previous = e;
  }
}

TEST_CASE("heat geodesic: localized query — heat exact, Poisson right-hand side measured") {
  const Mesh m = make_icosphere(5);
  const HeatGeodesic geo(m);
  HeatGeodesicWorkspace ws;
  const int32_t c = 1234;
  const std::vector<int32_t> patch = sphere_disk(m, c, 0.5);
  std::vector<double> full(m.num_vertices()), flux(patch.size()), trunc(patch.size());
  geo.query_full(c, full, ws);
  geo.query(c, patch, flux, ws, HeatGeodesicOptions::PoissonRhs::BoundaryFlux);
  geo.query(c, patch, trunc, ws, HeatGeodesicOptions::PoissonRhs::Truncated);
  double e_flux = 0, e_trunc = 0, e_full = 0, diff = 0;
  for (size_t k = 0; k < patch.size(); ++k) {
    const double exact = great_circle(m, c, patch[k]);
    e_flux += std::abs(flux[k] - exact) / patch.size();
    e_trunc += std::abs(trunc[k] - exact) / patch.size();
    e_full += std::abs(full[patch[k]] - exact) / patch.size();
    diff = std::max(diff, std::abs(flux[k] - full[patch[k]]));
  }
  MESSAGE("E_d full " << e_full << ", local boundary-flux " << e_flux << ", local truncated " << e_trunc
                      << ", max |local - full| " << diff);
  CHECK(flux[0] == 0.0);
  // The truncated right-hand side bends the distance (net source -> uniform sink):
  // measured ~1.2e-2 against ~4e-3 for the boundary flux and the full solve.
  CHECK(e_trunc > 2 * e_flux);
  CHECK(e_flux < 1.5 * e_full);
  CHECK(diff < 0.02);
}

// Errors by band of the exact distance (relative to the patch's largest):
// inner half and outer tenth, and the largest |local - full|.
struct RimErrors {
  double inner = 0, outer = 0, vs_full = 0, mean = 0;
};
RimErrors rim_errors(const Mesh& m, int32_t c, const std::vector<int32_t>& patch, const std::vector<double>& d,
                     const std::vector<double>& full) {
  double rmax = 0;
  for (int32_t j : patch) rmax = std::max(rmax, great_circle(m, c, j));
  RimErrors e;
  int64_t ni = 0, no = 0;
  for (size_t k = 0; k < patch.size(); ++k) {
    const double r = great_circle(m, c, patch[k]), err = std::abs(d[k] - r);
    e.mean += err / patch.size();
    if (patch[k] != c && r < 0.5 * rmax) e.inner += err, ++ni;
    if (r >= 0.9 * rmax) e.outer += err, ++no;
    e.vs_full = std::max(e.vs_full, std::abs(d[k] - full[patch[k]]));
  }
  e.inner /= ni;
  e.outer /= no;
  return e;
}

TEST_CASE("heat geodesic: localized on a graph-metric disk — the rim as accurate as the interior, as the full solve") {
  // The CLI's patches are Dijkstra disks (graph metric): on an icosphere their
  // boundary is no level set of the distance, and truncating X at it bent the
  // outer tenth (icosphere 7: 2.7e-2 against 1.3e-3 inside; docs/logmap.md).
  const Mesh m = make_icosphere(5);  // h ~ 0.038
  const int32_t c = 1234;
  const int32_t count = static_cast<int32_t>(sphere_disk(m, c, 0.7).size());
  const PatchGrower grower = prepare_patch_grower(m);
  PatchWorkspace pws;
  std::vector<int32_t> patch;
  grow_patch_vertices(grower, c, geodesic_disk(count), pws, patch);
  HeatGeodesicOptions off;
  off.level_set_rim = false;
  const HeatGeodesic geo(m), geo_off(m, off);
  HeatGeodesicWorkspace ws;
  std::vector<double> full(m.num_vertices()), d(patch.size()), d_off(patch.size());
  geo.query_full(c, full, ws);
  geo.query(c, patch, d, ws);
  geo_off.query(c, patch, d_off, ws);
  const RimErrors e = rim_errors(m, c, patch, d, full), e_off = rim_errors(m, c, patch, d_off, full);
  MESSAGE("graph disk E_d inner/outer: level-set rim " << e.inner << " / " << e.outer << " (|local - full| <= "
                                                       << e.vs_full << "), patch rim " << e_off.inner << " / "
                                                       << e_off.outer << " (" << e_off.vs_full << ")");
  CHECK(d[0] == 0.0);
  CHECK(e.outer <= 2 * e.inner);
  CHECK(e_off.outer > 3 * e_off.inner);  // the failure the level-set rim removes
  CHECK(e.vs_full < 0.25 * e_off.vs_full);
  // A one-sided patch (the center on its boundary): almost all of it lies beyond
  // the ring's level set and is continued along X.
  std::vector<int32_t> half{c};
  for (int32_t j : sphere_disk(m, c, 0.6))
    if (j != c && (m.x[j] - m.x[c]) * 0.6 + (m.y[j] - m.y[c]) * 0.8 >= 0) half.push_back(j);
  std::vector<double> dh(half.size()), dh_off(half.size());
  geo.query(c, half, dh, ws);
  geo_off.query(c, half, dh_off, ws);
  const RimErrors eh = rim_errors(m, c, half, dh, full), eh_off = rim_errors(m, c, half, dh_off, full);
  MESSAGE("half disk E_d: level-set rim " << eh.mean << ", patch rim " << eh_off.mean);
  CHECK(eh.mean < 2 * rim_errors(m, c, patch, d, full).mean);
  CHECK(eh.vs_full < 0.02);
}

TEST_CASE("heat geodesic: planar disk, Euclidean distance from the center") {
  const Mesh m = make_disk(40);  // h ~ 0.025
  const HeatGeodesic geo(m);
  HeatGeodesicWorkspace ws;
  const DemLogMap dem(m);
  DemWorkspace dws;
  std::vector<int32_t> patch(m.num_vertices());
  const int32_t k = dem.query(0, m.num_vertices() / 4, std::numeric_limits<double>::infinity(), patch, {}, {}, dws);
  patch.resize(k);
  std::vector<double> d(k);
  geo.query(0, patch, d, ws);
  double e = 0, worst = 0;
  for (int32_t p = 0; p < k; ++p) {
    const double r = std::hypot(m.x[patch[p]], m.y[patch[p]]);
    e += std::abs(d[p] - r) / k;
    worst = std::max(worst, std::abs(d[p] - r));
  }
  MESSAGE("disk: mean error " << e << ", max " << worst);
  CHECK(e < 0.01);
  CHECK(worst < 0.03);
}

TEST_CASE("heat geodesic: bad queries are usage errors and leave the workspace clean") {
  const Mesh m = make_icosphere(3);
  const HeatGeodesic geo(m);
  HeatGeodesicWorkspace ws;
  const std::vector<int32_t> patch = sphere_disk(m, 5, 0.6);
  std::vector<double> d(patch.size()), again(patch.size());
  geo.query(5, patch, d, ws);
  auto code = [&](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::Internal;
  };
  CHECK(code([&] { geo.query(-1, patch, d, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { geo.query(m.num_vertices(), patch, d, ws); }) == ErrorCode::BadUsage);
  std::vector<int32_t> without(patch.begin() + 1, patch.end());
  std::vector<double> dw(without.size());
  CHECK(code([&] { geo.query(5, without, dw, ws); }) == ErrorCode::BadUsage);  // source not in the patch
  std::vector<int32_t> dup = patch;
  dup.push_back(patch[3]);
  std::vector<double> dd(dup.size());
  CHECK(code([&] { geo.query(5, dup, dd, ws); }) == ErrorCode::BadUsage);
  std::vector<int32_t> out_of_range = patch;
  out_of_range[2] = m.num_vertices() + 4;
  CHECK(code([&] { geo.query(5, out_of_range, d, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { geo.query(5, std::span<const int32_t>(), std::span<double>(), ws); }) == ErrorCode::BadUsage);
  std::vector<double> wrong(3);
  CHECK(code([&] { geo.query(5, patch, wrong, ws); }) == ErrorCode::BadUsage);
  HeatGeodesicOptions bad;
  bad.t_factor = -1;
  CHECK(code([&] { HeatGeodesic g(m, bad); }) == ErrorCode::BadUsage);
  // Same answer after the failed calls: the region marks were released.
  geo.query(5, patch, again, ws);
  CHECK(again == d);
}

TEST_CASE("heat geodesic: queries from several threads give the single-thread answers") {
  const Mesh m = make_icosphere(4);
  const HeatGeodesic geo(m);
  std::vector<int32_t> sources = {3, 100, 1000, 2500};
  std::vector<std::vector<int32_t>> patches;
  std::vector<std::vector<double>> serial;
  HeatGeodesicWorkspace ws;
  for (int32_t s : sources) {
    patches.push_back(sphere_disk(m, s, 0.7));
    serial.emplace_back(patches.back().size());
    geo.query(s, patches.back(), serial.back(), ws);
  }
  std::vector<std::vector<double>> parallel(sources.size());
  std::vector<std::thread> threads;
  for (size_t q = 0; q < sources.size(); ++q)
    threads.emplace_back([&, q] {
      HeatGeodesicWorkspace w;
      parallel[q].resize(patches[q].size());
      geo.query(sources[q], patches[q], parallel[q], w);
    });
  for (auto& t : threads) t.join();
  for (size_t q = 0; q < sources.size(); ++q) CHECK(parallel[q] == serial[q]);
}

TEST_CASE("heat geodesic: given factors (e.g. from a cache) give the same distances; another mesh's are refused") {
  const Mesh m = make_icosphere(3);
  const HeatGeodesic own(m);
  HeatGeodesicWorkspace ws;
  std::vector<double> a(static_cast<size_t>(m.num_vertices())), b(a.size());
  own.query_full(5, a, ws);
  const HeatGeodesic given(m, HeatGeodesicOptions{}, HeatGeodesicFactors{own.heat_factor(), own.poisson_factor()});
  given.query_full(5, b, ws);
  CHECK(a == b);
  const Mesh other = make_icosphere(2);
  const HeatGeodesic small(other);
  CHECK_THROWS_AS(HeatGeodesic(m, HeatGeodesicOptions{}, HeatGeodesicFactors{small.heat_factor(), small.poisson_factor()}),
                  Error);
}

TEST_CASE("heat geodesic: mass_blend gives M = (1 - b) lumped + b consistent in the heat operator") {
  const Mesh m = make_icosphere(2);
  HeatGeodesicOptions o;
  o.mass_blend = 0.5;
  CscMatrix H, P;
  const double t = HeatGeodesic::operators(m, o, H, P);
  // Oracle: the consistent mass matrix integrated in the test, int phi_i phi_j = area (1 + [i = j]) / 12.
  std::vector<Eigen::Triplet<double>> tr;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const Eigen::Vector3d a(m.x[v[0]], m.y[v[0]], m.z[v[0]]), b(m.x[v[1]], m.y[v[1]], m.z[v[1]]),
        c(m.x[v[2]], m.y[v[2]], m.z[v[2]]);
    const double area = 0.5 * (b - a).cross(c - a).norm();
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) tr.emplace_back(v[r], v[s], area * (r == s ? 2.0 : 1.0) / 12);
  }
  SpMat Mc(m.num_vertices(), m.num_vertices());
  Mc.setFromTriplets(tr.begin(), tr.end());
  const SpMat want = 0.5 * to_eigen(mass_matrix_as_csc(m)) + 0.5 * Mc - t * to_eigen(cotan_laplacian(m));
  CHECK((to_eigen(H) - want).norm() < 1e-12 * want.norm());
  HeatGeodesicOptions bad;
  bad.mass_blend = 1.5;
  CHECK_THROWS_AS(HeatGeodesic(m, bad), Error);
}

TEST_CASE("heat geodesic: underflowing heat is counted, with a t that avoids it") {
  const Mesh m = make_icosphere(4);  // h ~ 0.076
  HeatGeodesicOptions tiny;
  tiny.t_factor = 1e-9;  // the heat falls by ~t / h^2 per edge: it underflows ~20 edges from the source
  const HeatGeodesic geo(m, tiny);
  HeatGeodesicWorkspace ws;
  std::vector<double> d(m.num_vertices());
  geo.query_full(7, d, ws);
  int64_t zero = 0;
  for (double x : ws.h) zero += !(x >= std::numeric_limits<double>::min());
  MESSAGE("t = " << geo.time() << ": " << ws.underflow << " vertices underflowed, t avoiding it " << ws.t_no_underflow);
  CHECK(ws.underflow == zero);
  REQUIRE(ws.underflow > 0);
  CHECK(ws.t_no_underflow > geo.time());
  // Localized: only the patch's vertices count.
  const std::vector<int32_t> near = sphere_disk(m, 7, 0.5), far = sphere_disk(m, 7, 2.5);
  std::vector<double> dn(near.size()), df(far.size());
  geo.query(7, near, dn, ws);
  CHECK(ws.underflow == 0);
  CHECK(ws.t_no_underflow == 0.0);
  geo.query(7, far, df, ws);
  CHECK(ws.underflow > 0);
  // The suggested t: no underflow over the whole sphere.
  HeatGeodesicOptions fixed;
  fixed.t_factor = ws.t_no_underflow / (geo.mean_edge_length() * geo.mean_edge_length());
  const HeatGeodesic geo2(m, fixed);
  geo2.query_full(7, d, ws);
  CHECK(ws.underflow == 0);
  const HeatGeodesic geo_default(m);
  geo_default.query_full(7, d, ws);
  CHECK(ws.underflow == 0);
}
