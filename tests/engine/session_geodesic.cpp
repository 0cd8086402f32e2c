// Multi-source heat geodesic distance through the Session
// (engine/src/session_geodesic.cpp).
// Oracles: an independent dense implementation of the heat method written here
// (cotan Laplacian, lumped mass, per-face gradient of log u, divergence and the
// regularized Poisson step solved by Eigen's dense LDLT) on a small sphere;
// great-circle distances to the nearest source on a fine unit icosphere; the
// single-source query (one vertex source must give the same bits); and the
// component rule (+infinity without a source, minimum 0 over each component's sources).
#include <Eigen/Dense>
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/session.hpp"
#include "tests/engine/session_test_support.hpp"

using namespace locus;
using locus::test::code_of;

namespace {

using Vec3 = Eigen::Vector3d;

Vec3 pos(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }

// The heat method of Crane et al. on dense matrices: (M - tL) u = b, X = -grad log u / |.| per
// face (grad u where a corner is not positive), (-L + eps M) phi = -div X, eps = 1e-6 tr(-L) / tr(M).
std::vector<double> dense_heat_method(const Mesh& m, const std::vector<MeshPoint>& sources, double t_factor) {
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  double hsum = 0;
  int64_t ne = 0;
  std::vector<std::array<int32_t, 3>> tri(nf);
  for (int32_t f = 0; f < nf; ++f) {
    tri[f] = {m.f0[f], m.f1[f], m.f2[f]};
    const double area = 0.5 * (pos(m, tri[f][1]) - pos(m, tri[f][0])).cross(pos(m, tri[f][2]) - pos(m, tri[f][0])).norm();
    for (int c = 0; c < 3; ++c) {
      const int32_t i = tri[f][c], j = tri[f][(c + 1) % 3], k = tri[f][(c + 2) % 3];
      const Vec3 a = pos(m, j) - pos(m, i), b = pos(m, k) - pos(m, i);
      const double cot = a.dot(b) / a.cross(b).norm();  // angle at i, opposite edge jk
      L(j, k) += 0.5 * cot;
      L(k, j) += 0.5 * cot;
      L(j, j) -= 0.5 * cot;
      L(k, k) -= 0.5 * cot;
      mass[i] += area / 3;
      if (i < j) {  // closed mesh: every edge runs i -> j (i < j) in exactly one of its two faces
        hsum += (pos(m, j) - pos(m, i)).norm();
        ++ne;
      }
    }
  }
  const double h = hsum / static_cast<double>(ne), t = t_factor * h * h;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (const MeshPoint& p : sources) {
    if (p.face < 0) {
      b[p.vertex] += 1;
    } else {
      for (int c = 0; c < 3; ++c) b[tri[p.face][c]] += p.bary[c];
    }
  }
  const Eigen::MatrixXd A = Eigen::MatrixXd(mass.asDiagonal()) - t * L;
  const Eigen::VectorXd u = A.ldlt().solve(b);
  Eigen::VectorXd div = Eigen::VectorXd::Zero(n);
  for (int32_t f = 0; f < nf; ++f) {
    const std::array<int32_t, 3>& v = tri[f];
    const Vec3 p0 = pos(m, v[0]), p1 = pos(m, v[1]), p2 = pos(m, v[2]);
    const Vec3 nrm = (p1 - p0).cross(p2 - p0);
    const double area2 = nrm.norm();
    const Vec3 N = nrm / area2;
    const bool positive = u[v[0]] > 0 && u[v[1]] > 0 && u[v[2]] > 0;
    double val[3];
    for (int c = 0; c < 3; ++c) val[c] = positive ? std::log(u[v[c]]) : u[v[c]];
    Vec3 g = Vec3::Zero();
    const Vec3 P[3] = {p0, p1, p2};
    for (int c = 0; c < 3; ++c) g += val[c] * N.cross(P[(c + 2) % 3] - P[(c + 1) % 3]);  // edge opposite corner c, ccw
    g /= area2;
    const Vec3 X = g.norm() > 0 ? Vec3(-g / g.norm()) : Vec3::Zero();
    for (int c = 0; c < 3; ++c) {
      const Vec3 e1 = P[(c + 1) % 3] - P[c], e2 = P[(c + 2) % 3] - P[c];
      const Vec3 o1 = P[c] - P[(c + 2) % 3], o2 = P[(c + 1) % 3] - P[(c + 2) % 3];  // angle at corner c+2 (opposite e1)
      const Vec3 q1 = P[c] - P[(c + 1) % 3], q2 = P[(c + 2) % 3] - P[(c + 1) % 3];  // angle at corner c+1 (opposite e2)
      const double cot1 = o1.dot(o2) / o1.cross(o2).norm(), cot2 = q1.dot(q2) / q1.cross(q2).norm();
      div[v[c]] += 0.5 * (cot1 * e1.dot(X) + cot2 * e2.dot(X));
    }
  }
  // HeatGeodesicOptions::poisson_rel: eps = 1e-5 mean(diag(-L)) / area.
  const double eps = 1e-5 * (-L.trace()) / static_cast<double>(n) / mass.sum();
  const Eigen::MatrixXd P = -L + eps * Eigen::MatrixXd(mass.asDiagonal());
  const Eigen::VectorXd phi = P.ldlt().solve(-div);
  double lo = std::numeric_limits<double>::infinity();
  for (const MeshPoint& p : sources) {
    double value = 0;
    if (p.face < 0) value = phi[p.vertex];
    else
      for (int c = 0; c < 3; ++c) value += p.bary[c] * phi[tri[p.face][c]];
    lo = std::min(lo, value);
  }
  std::vector<double> d(n);
  for (int32_t i = 0; i < n; ++i) d[i] = phi[i] - lo;
  return d;
}

Mesh two_spheres() {
  Mesh a = make_icosphere(2), b = make_icosphere(2);
  const int32_t n = a.num_vertices();
  for (int32_t i = 0; i < b.num_vertices(); ++i) a.add_vertex(b.x[i] + 3.0, b.y[i], b.z[i]);
  for (int32_t f = 0; f < b.num_faces(); ++f) a.add_triangle(b.f0[f] + n, b.f1[f] + n, b.f2[f] + n);
  return a;
}

}  // namespace

TEST_CASE("session multi-source geodesic: equals a dense solve of the heat method") {
  const Mesh m = make_icosphere(2);  // 162 vertices: dense is cheap
  const Session s(m);
  const std::vector<MeshPoint> sources{MeshPoint::at_vertex(0), MeshPoint::at_vertex(40),
                                       MeshPoint::in_face(100, 0.2, 0.3, 0.5)};
  for (double tf : {1.0, 3.0}) {
    const std::vector<double> d = s.geodesic_distance(sources, HeatQuery{tf});
    const std::vector<double> ref = dense_heat_method(m, sources, tf);
    double worst = 0, dmax = 0;
    for (int32_t i = 0; i < m.num_vertices(); ++i) {
      worst = std::max(worst, std::abs(d[i] - ref[i]));
      dmax = std::max(dmax, ref[i]);
    }
    INFO("t_factor " << tf << ": max |session - dense| = " << worst << ", max distance " << dmax);
    CHECK(dmax > 0.5);
    CHECK(worst < 1e-9 * dmax);
  }
}

TEST_CASE("session multi-source geodesic: nearest great circle on the unit sphere") {
  const Mesh m = make_icosphere(5);
  const Session s(m);
  // Two vertex sources and a point inside a face.
  const int32_t f = 5000;
  const MeshPoint fp = MeshPoint::in_face(f, 0.5, 0.25, 0.25);
  Vec3 q = 0.5 * pos(m, m.f0[f]) + 0.25 * pos(m, m.f1[f]) + 0.25 * pos(m, m.f2[f]);
  q.normalize();
  const std::vector<MeshPoint> sources{MeshPoint::at_vertex(0), MeshPoint::at_vertex(7), fp};
  auto mean_error = [&](const std::vector<double>& d) {
    double err = 0;
    for (int32_t i = 0; i < m.num_vertices(); ++i) {
      const Vec3 p = pos(m, i).normalized();
      double exact = std::numeric_limits<double>::infinity();
      for (const Vec3& c : {pos(m, 0).normalized(), pos(m, 7).normalized(), q})
        exact = std::min(exact, std::acos(std::clamp(p.dot(c), -1.0, 1.0)));
      err += std::abs(d[i] - exact);
    }
    return err / m.num_vertices();
  };
  // The heat method smooths the distance at the sources and along the
  // bisectors over a width ~ sqrt(t): the bound is looser at the default 4 h^2
  // (chosen for the log maps' angles, docs/logmap.md) than at h^2.
  const double err1 = mean_error(s.geodesic_distance(sources, HeatQuery{1.0}));
  INFO("mean |d - nearest great circle| at t = h^2: " << err1);
  CHECK(err1 < 0.02);
  const std::vector<double> d = s.geodesic_distance(sources);
  const double err = mean_error(d);
  INFO("mean |d - nearest great circle| at the default t: " << err);
  CHECK(err < 0.045);
  CHECK(*std::min_element(d.begin(), d.end()) > -0.01);
  // The vertex-id form is the same query.
  const std::vector<int32_t> ids{0, 7};
  const std::vector<double> a = s.geodesic_distance_from_vertices(ids);
  const std::vector<MeshPoint> pts{MeshPoint::at_vertex(0), MeshPoint::at_vertex(7)};
  CHECK(a == s.geodesic_distance(pts));
  CHECK(s.stats().heat_engines == 2);  // t = h^2 and the default t; one factorization each served every query
}

TEST_CASE("session multi-source geodesic: one vertex source is the single-source query, bit for bit") {
  const Session s(make_icosphere(3));
  const std::vector<MeshPoint> one{MeshPoint::at_vertex(17)};
  CHECK(s.geodesic_distance(one) == s.geodesic_distance(17));
}

TEST_CASE("session multi-source geodesic: components, repeated sources and errors") {
  const Mesh m = two_spheres();
  const Session s(m);
  const int32_t half = m.num_vertices() / 2;
  std::vector<MeshPoint> first{MeshPoint::at_vertex(3), MeshPoint::at_vertex(3)};
  std::vector<double> d = s.geodesic_distance(first);
  for (int32_t i = half; i < m.num_vertices(); ++i) REQUIRE(std::isnan(d[i]));  // no value
  CHECK(d[3] == 0.0);
  const std::vector<MeshPoint> both{MeshPoint::at_vertex(3), MeshPoint::at_vertex(half + 10), MeshPoint::at_vertex(half + 50)};
  d = s.geodesic_distance(both);
  CHECK(d[3] == 0.0);
  CHECK(std::min(d[half + 10], d[half + 50]) == 0.0);
  for (double x : d) CHECK(std::isfinite(x));

  const std::vector<MeshPoint> none;
  CHECK(code_of([&] { s.geodesic_distance(none); }) == ErrorCode::BadUsage);
  const std::vector<MeshPoint> bad_face{MeshPoint::in_face(m.num_faces(), 1, 0, 0)};
  CHECK(code_of([&] { s.geodesic_distance(bad_face); }) == ErrorCode::BadUsage);
  const std::vector<MeshPoint> bad_weights{MeshPoint::in_face(0, 0.5, 0.6, -0.1)};
  CHECK(code_of([&] { s.geodesic_distance(bad_weights); }) == ErrorCode::BadUsage);
  const std::vector<MeshPoint> bad_vertex{MeshPoint::at_vertex(-1)};
  CHECK(code_of([&] { s.geodesic_distance(bad_vertex); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.geodesic_distance(both, HeatQuery{1.0, 0.01}); }) == ErrorCode::BadUsage);  // t_factor only
  CHECK(code_of([&] { s.geodesic_distance(0, HeatQuery{1.0, 0.01}); }) == ErrorCode::BadUsage);
  std::vector<double> small(3);
  CHECK(code_of([&] { s.geodesic_distance(both, small); }) == ErrorCode::BadUsage);
}
