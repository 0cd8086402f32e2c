// The operator choice of a Session (engine/include/locus/engine/operator_choice.hpp):
// auto, cotan and robust on clean and defective meshes.
// Oracles: the great-circle distance acos(p . p0) on a unit icosphere with
// planted defects (kernels/.../mesh_defects_plant.hpp: fins, bowties, zero-area
// faces, needles, a flipped patch, unreferenced vertices, duplicate faces), the
// clean mesh's own error as the bound (within 1.5x); heat conservation
// (sum_j m_j (M - tL)^-1_ji = 1 for every source i, since L's rows sum to zero);
// and the cotan Session's bits for auto on a clean mesh.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_defects_plant.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/robust_laplacian.hpp"
#include "locus/locus.h"
#include "locus/session.hpp"
#include "tests/engine/fold_mesh.hpp"
#include "tests/engine/session_test_support.hpp"

using namespace locus;
using locus::test::code_of;

namespace {

double great_circle(const Mesh& m, int32_t a, int32_t b) {
  const double c = m.x[a] * m.x[b] + m.y[a] * m.y[b] + m.z[a] * m.z[b];
  return std::acos(std::clamp(c, -1.0, 1.0));
}

// Mean |d - great circle| over the vertices 0..nv0-1 (the icosphere's own).
double mean_error(const Mesh& m, const std::vector<double>& d, int32_t nv0, int32_t source) {
  double sum = 0;
  for (int32_t v = 0; v < nv0; ++v) sum += std::abs(d[v] - great_circle(m, v, source));
  return sum / nv0;
}

Session session_with(const Mesh& m, OperatorChoice c) {
  SessionOptions o;
  o.mesh_operator = c;
  return Session(Mesh(m), o);
}

}  // namespace

TEST_CASE("Session operator auto: a clean mesh runs on the cotan operator, bit for bit") {
  const Mesh m = make_icosphere(3);
  const Session a{Mesh(m)};
  const Session c = session_with(m, OperatorChoice::Cotan);
  CHECK_FALSE(a.operator_report().robust);
  CHECK(a.operator_report().checked);
  CHECK_FALSE(a.operator_report().any_defect());
  CHECK(a.geodesic_distance(5) == c.geodesic_distance(5));
  const int32_t src[1] = {5}, tgt[2] = {0, 100};
  CHECK(a.heat_values(ConstView<int32_t>(src, 1), ConstView<int32_t>(tgt, 2)) ==
        c.heat_values(ConstView<int32_t>(src, 1), ConstView<int32_t>(tgt, 2)));
}

TEST_CASE("Session operator: heat distance per planted defect within 1.5x the clean mesh's error") {
  const int level = 5, sites = 8, source = 0;
  const Mesh clean = make_icosphere(level);
  const int32_t nv0 = clean.num_vertices();
  const double clean_error = mean_error(clean, Session(Mesh(clean)).geodesic_distance(source), nv0, source);
  MESSAGE("icosphere " << level << " clean (cotan): mean error " << clean_error);
  CHECK(clean_error < 0.01);
  for (int k = 0; k < kNumPlantedDefects; ++k) {
    const PlantedDefect kind = static_cast<PlantedDefect>(k);
    const std::string name = planted_defect_name(kind);
    CAPTURE(name);
    const Mesh m = plant_mesh_defect(clean, kind, sites);
    // The cotan operator refuses every kind (at construction, or the heat method its needles).
    CHECK(code_of([&] { session_with(m, OperatorChoice::Cotan).geodesic_distance(source); }) == ErrorCode::BadInput);
    const Session s{Mesh(m)};  // auto
    const OperatorReport op = s.operator_report();
    CHECK(op.robust);
    CHECK(op.any_defect());
    const std::vector<double> d = s.geodesic_distance(source);
    const double e = mean_error(m, d, nv0, source);
    MESSAGE(name << " x" << sites << ": mean error " << e << " (" << e / clean_error
                                      << "x clean); " << op.reason());
    CHECK(e <= 1.5 * clean_error);
    // Unreferenced vertices have no value; every other vertex has one.
    std::vector<char> referenced(static_cast<size_t>(m.num_vertices()), 0);
    for (const int32_t v : m.face_vertices) referenced[v] = 1;
    int64_t nan_mismatch = 0;
    for (int32_t v = 0; v < m.num_vertices(); ++v) nan_mismatch += std::isnan(d[v]) != !referenced[v];
    CHECK(nan_mismatch == 0);
    // Localized (the geodesic request, 20 % disk): close to the whole-mesh answer inside the patch.
    GeodesicRequest req;
    req.source = source;
    req.fraction = 0.2;
    const GeodesicReport r = s.geodesic(req);
    double worst = 0;
    int64_t inside = 0;
    for (int32_t v = 0; v < nv0; ++v)
      if (r.valid[v] == 1) {
        ++inside;
        worst = std::max(worst, std::abs(r.distance[v] - great_circle(m, v, source)));
      }
    CHECK(inside > nv0 / 10);
    CHECK(worst < 0.05);
  }
}

TEST_CASE("Session operator robust: heat values conserve heat with the robust mass") {
  const Mesh m = plant_mesh_defect(make_icosphere(3), PlantedDefect::Fin, 4);
  const Session s{Mesh(m)};
  REQUIRE(s.operator_report().robust);
  const RobustOperators R = robust_laplacian(m);
  std::vector<int32_t> all(static_cast<size_t>(m.num_vertices()));
  for (int32_t v = 0; v < m.num_vertices(); ++v) all[v] = v;
  const int32_t src[2] = {0, 37};
  const std::vector<double> h = s.heat_values(ConstView<int32_t>(src, 2), ConstView<int32_t>(all));
  for (int k = 0; k < 2; ++k) {
    double total = 0;
    for (int32_t v = 0; v < m.num_vertices(); ++v) total += R.mass[v] * h[k * all.size() + v];
    CHECK(total == doctest::Approx(1.0).epsilon(1e-9));
  }
  // The log map needs one tangent plane per vertex: refused, naming why.
  CHECK(code_of([&] { s.logmap(0, 0.05); }) == ErrorCode::BadInput);
  // Forced robust on a clean mesh: close to the cotan answer (the icosphere is Delaunay).
  const Mesh c = make_icosphere(4);
  const std::vector<double> dc = session_with(c, OperatorChoice::Cotan).geodesic_distance(0);
  const std::vector<double> dr = session_with(c, OperatorChoice::Robust).geodesic_distance(0);
  double diff = 0;
  for (size_t v = 0; v < dc.size(); ++v) diff = std::max(diff, std::abs(dc[v] - dr[v]));
  CHECK(diff < 1e-3);
}

TEST_CASE("C API: locus_session_create_ex takes the operator choice") {
  const Mesh m = plant_mesh_defect(make_icosphere(2), PlantedDefect::Fin, 2);
  std::vector<double> xyz;
  for (int32_t v = 0; v < m.num_vertices(); ++v) xyz.insert(xyz.end(), {m.x[v], m.y[v], m.z[v]});
  const std::vector<int32_t> tris(m.face_vertices.begin(), m.face_vertices.end());
  locus_session_options opt{LOCUS_OPERATOR_COTAN, 0};
  locus_session* s = nullptr;
  CHECK(locus_session_create_ex(xyz.data(), m.num_vertices(), tris.data(), m.num_faces(), &opt, &s) == LOCUS_BAD_INPUT);
  CHECK(s == nullptr);
  opt.mesh_operator = 7;
  CHECK(locus_session_create_ex(xyz.data(), m.num_vertices(), tris.data(), m.num_faces(), &opt, &s) == LOCUS_BAD_USAGE);
  REQUIRE(locus_session_create(xyz.data(), m.num_vertices(), tris.data(), m.num_faces(), &s) == LOCUS_OK);  // auto
  CHECK(locus_session_operator(s) == LOCUS_OPERATOR_ROBUST);
  std::vector<double> d(static_cast<size_t>(m.num_vertices()));
  CHECK(locus_geodesic_distance(s, 0, d.data()) == LOCUS_OK);
  CHECK(d[0] == 0.0);
  for (int32_t v = 0; v < m.num_vertices(); ++v) CHECK(std::isfinite(d[v]));
  locus_session_destroy(s);
  CHECK(locus_session_operator(nullptr) == -1);
}

TEST_CASE("Session operator auto: where the cotan heat method fails on a clean mesh, the robust operator answers") {
  const Mesh m = locus::test::fold_mesh();
  GeodesicRequest req;
  req.source = 0;
  const Session cotan = session_with(m, OperatorChoice::Cotan);
  CHECK(code_of([&] { (void)cotan.geodesic(req); }) == ErrorCode::Numerical);
  const Session a{Mesh(m)};
  CHECK_FALSE(a.operator_report().robust);  // the mesh is clean: auto chose cotan
  const GeodesicReport r = a.geodesic(req);
  CHECK(r.operator_fallback.find("negative") != std::string::npos);
  REQUIRE(!r.warnings.empty());
  CHECK(r.warnings.back() == r.operator_fallback);
  // The same numbers as the robust operator's, and distances, not noise: 0 at
  // the source, positive elsewhere, below the shortest edge path (Dijkstra
  // over the edges, an upper bound of the surface distance) by at most 10%.
  CHECK(r.distance == session_with(m, OperatorChoice::Robust).geodesic(req).distance);
  std::vector<double> path(12, 1e300);
  path[0] = 0;
  for (int round = 0; round < 12; ++round)
    for (int32_t f = 0; f < m.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int32_t t[3] = {m.f0[f], m.f1[f], m.f2[f]};
        const int32_t u = t[k], v = t[(k + 1) % 3];
        const double e = std::hypot(m.x[u] - m.x[v], m.y[u] - m.y[v], m.z[u] - m.z[v]);
        path[v] = std::min(path[v], path[u] + e);
        path[u] = std::min(path[u], path[v] + e);
      }
  CHECK(std::abs(r.distance[0]) <= 1e-9 * r.max_distance);
  for (int v = 1; v < 12; ++v) {
    CHECK(r.distance[v] > 0);
    CHECK(r.distance[v] <= 1.1 * path[v]);
  }
}

TEST_CASE("Session operator auto: an unreferenced vertex has no value (NaN) in adf, hks and heat") {
  // The oracle: the same queries on the mesh without the lone vertex (the
  // robust operator of the rest is the same surface, the same h and t).
  const Mesh clean = make_icosphere(2);
  Mesh m = clean;
  m.add_vertex(3, 3, 3);
  const int32_t lone = clean.num_vertices();
  const Session a{Mesh(m)};
  REQUIRE(a.operator_report().robust);
  const Session c = session_with(clean, OperatorChoice::Robust);
  AdfRequest q;
  q.all = true;
  const HeatSignatureReport ra = a.adf(q), rc = c.adf(q);
  REQUIRE(ra.values.size() == static_cast<size_t>(lone + 1));
  CHECK(std::isnan(ra.values[lone]));
  for (int32_t v = 0; v < lone; ++v) CHECK(ra.values[v] == doctest::Approx(rc.values[v]).epsilon(1e-9));
  HksRequest k;
  k.ts = {"1h2", "4h2"};
  k.vertices = {7, lone};
  const HeatSignatureReport rk = a.hks(k);
  REQUIRE(rk.values.size() == 4);
  CHECK(rk.values[0] > 0);
  CHECK(rk.values[1] > 0);
  CHECK(std::isnan(rk.values[2]));
  CHECK(std::isnan(rk.values[3]));
  HeatRequest h;
  h.source = {0};
  h.target = {5, lone};
  const HeatReport rh = a.heat(h);
  h.target = {5};
  CHECK(rh.values[0] == doctest::Approx(c.heat(h).values[0]).epsilon(1e-9));
  CHECK(std::isnan(rh.values[1]));
  CHECK(rh.total == rh.values[0]);
}
