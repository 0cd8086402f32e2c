// Tests for locus::Session (engine/include/locus/session.hpp).
// Oracles: great-circle distances on a unit icosphere (heat geodesic converges
// to them), an Eigen sparse LDLT solve of M - tL for heat values, the direct
// pipeline calls (HeatGeodesic, HeatLogMap, cvt_lloyd, the deform pipeline)
// whose numbers a Session must reproduce bit for bit, the scaling law of the
// heat operator after set_positions, and single-threaded runs for concurrent ones.
#include "locus/session.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <cmath>
#include <thread>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/deform/deform.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "tests/kernels/matrix_fixtures.hpp"
#include "tests/engine/session_test_support.hpp"

using namespace locus;
using SpMat = Eigen::SparseMatrix<double>;
using locus::test::code_of;
using locus::test::to_eigen;

namespace {

std::vector<double> interleaved(const Mesh& m) {
  std::vector<double> xyz;
  for (int32_t i = 0; i < m.num_vertices(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
  return xyz;
}

}  // namespace

TEST_CASE("session: geodesic distance equals HeatGeodesic and approaches great-circle distances") {
  const Mesh m = make_icosphere(4);  // 2562 vertices
  const Session s(m);
  CHECK(s.num_vertices() == m.num_vertices());
  CHECK(s.num_faces() == m.num_faces());
  const int32_t src = 17;
  const std::vector<double> d = s.geodesic_distance(src);

  const HeatGeodesic direct(m);  // the Session's default t is the pipeline's
  std::vector<double> dd(m.num_vertices());
  HeatGeodesicWorkspace ws;
  direct.query_full(src, dd, ws);
  CHECK(d == dd);  // bit for bit

  double err = 0;
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    const double c = m.x[i] * m.x[src] + m.y[i] * m.y[src] + m.z[i] * m.z[src];
    err += std::abs(d[i] - std::acos(std::clamp(c, -1.0, 1.0)));
  }
  err /= m.num_vertices();
  CHECK(err < 0.02);  // mean absolute error on the unit sphere (diameter pi)
  CHECK(d[src] == 0.0);
}

TEST_CASE("session: log map equals HeatLogMap on the same Dijkstra disk; one engine for geodesic and log map") {
  const Mesh m = make_icosphere(4);
  const Session s(m);
  const int32_t c = 100;
  const LogMapResult r = s.logmap(c, 0.05);
  const int32_t count = static_cast<int32_t>(std::lround(0.05 * m.num_vertices()));
  REQUIRE(static_cast<int32_t>(r.patch.size()) == count);
  CHECK(r.patch[0] == c);

  const DemLogMap dem(m);
  DemWorkspace dws;
  std::vector<int32_t> patch(count);
  dem.query(c, count, std::numeric_limits<double>::infinity(), patch, {}, {}, dws);
  CHECK(patch == r.patch);
  const HeatLogMap direct(m);  // the Session's default t is the pipeline's
  std::vector<double> dd(count), a(count), u(count), v(count);
  LogMapWorkspace ws;
  direct.query(c, patch, {dd, a, u, v}, ws);
  CHECK(u == r.u);
  CHECK(v == r.v);
  CHECK(dd == r.distance);
  for (size_t k = 0; k < r.patch.size(); ++k) CHECK(std::hypot(r.u[k], r.v[k]) == doctest::Approx(r.distance[k]).epsilon(1e-9));

  s.geodesic_distance(3);
  CHECK(s.stats().heat_engines == 1);  // the log map's factors served the distance query
}

TEST_CASE("session: heat values equal an Eigen solve of M - h^2 L; one factorization for repeated queries") {
  const Mesh m = make_random_sphere(1500, 3);
  const Session s(m);
  const std::vector<int32_t> sources{0, 5, 5, 77, 1200, 13, 14, 15, 16, 900};  // 10: two batches, a repeat
  const std::vector<int32_t> targets{3, 0, 1499, 77, 3, 640};
  const std::vector<double> hv = s.heat_values(sources, targets);
  REQUIRE(hv.size() == sources.size() * targets.size());

  const double h = mean_edge_length(m);
  CHECK(s.mean_edge_length() == h);
  Eigen::SimplicialLDLT<SpMat> ldlt(to_eigen(heat_operator(m, h * h)));
  REQUIRE(ldlt.info() == Eigen::Success);
  double worst = 0;
  for (size_t i = 0; i < sources.size(); ++i) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(m.num_vertices());
    e[sources[i]] = 1;
    const Eigen::VectorXd x = ldlt.solve(e);
    for (size_t k = 0; k < targets.size(); ++k)
      worst = std::max(worst, std::abs(hv[i * targets.size() + k] - x[targets[k]]) / x.cwiseAbs().maxCoeff());
  }
  CHECK(worst < 1e-12);
  // Symmetry of the operator: repeated sources give the same row.
  for (size_t k = 0; k < targets.size(); ++k) CHECK(hv[1 * targets.size() + k] == hv[2 * targets.size() + k]);

  s.heat_values(targets, sources);
  const SessionStats st = s.stats();
  CHECK(st.numeric_factorizations == 1);
  CHECK(st.symbolic_analyses == 1);
  CHECK(st.heat_engines == 0);  // heat values do not need the Poisson factor
}

TEST_CASE("session: set_positions rebuilds numeric factors, keeps the symbolic one, matches a fresh session") {
  const Mesh m = make_icosphere(3);
  Session s(m);
  const std::vector<int32_t> src{4, 9}, tgt{0, 1, 2, 50, 300};
  const std::vector<double> before = s.heat_values(src, tgt);
  const std::vector<double> d_before = s.geodesic_distance(4);

  // Scale by 2: h doubles, t = h^2 quadruples, M quadruples, L (cotan) is scale
  // invariant, so M - tL is 4 times the old operator and its inverse a quarter.
  std::vector<double> xyz = interleaved(m);
  for (double& c : xyz) c *= 2;
  s.set_positions(xyz);
  const std::vector<double> after = s.heat_values(src, tgt);
  for (size_t k = 0; k < after.size(); ++k) CHECK(after[k] == doctest::Approx(before[k] / 4).epsilon(1e-12));
  const std::vector<double> d_after = s.geodesic_distance(4);
  for (size_t k = 0; k < d_after.size(); ++k) CHECK(d_after[k] == doctest::Approx(2 * d_before[k]).epsilon(1e-9).scale(1));

  SessionStats st = s.stats();
  CHECK(st.positions_version == 1);
  CHECK(st.numeric_factorizations == 2);
  CHECK(st.symbolic_analyses == 1);  // same pattern: kept
  CHECK(st.heat_engines == 2);

  // An irregular change of positions against a fresh Session on the moved mesh.
  Mesh moved = m;
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    const double f = 1.0 + 0.2 * std::sin(3 * m.x[i]) * std::cos(2 * m.z[i]);
    moved.x[i] *= f;
    moved.y[i] *= f;
    moved.z[i] *= f;
  }
  s.set_positions(interleaved(moved));
  const Session fresh(moved);
  CHECK(s.heat_values(src, tgt) == fresh.heat_values(src, tgt));
  CHECK(s.geodesic_distance(9) == fresh.geodesic_distance(9));
  CHECK(s.mesh().x == moved.x);
  st = s.stats();
  CHECK(st.symbolic_analyses == 1);

  // Bad positions leave the Session as it was.
  std::vector<double> bad = interleaved(moved);
  bad[7] = NAN;
  CHECK(code_of([&] { s.set_positions(bad); }) == ErrorCode::BadInput);
  CHECK(code_of([&] { s.set_positions(std::vector<double>(5)); }) == ErrorCode::BadUsage);
  std::vector<double> flat = interleaved(moved);  // every vertex at the origin: zero-area faces
  std::fill(flat.begin(), flat.end(), 0.0);
  CHECK(code_of([&] { s.set_positions(flat); }) == ErrorCode::BadInput);
  CHECK(s.mesh().x == moved.x);
  CHECK(s.stats().positions_version == 2);
}

TEST_CASE("session: cvt equals cvt_lloyd; deform equals the deform pipeline") {
  const Mesh m = make_icosphere(3);  // 642 vertices
  const Session s(m);
  const CvtResult r = s.cvt(12, 3, 5);
  LloydOptions o;
  o.sites = 12;
  o.iterations = 3;
  o.seed = 5;
  const LloydResult lr = cvt_lloyd(m, o, {});
  CHECK(r.label == lr.label);
  REQUIRE(r.site_xyz.size() == 36);
  for (int32_t k = 0; k < 12; ++k) {
    const auto p = surface_point_position(m, lr.sites[k]);
    CHECK(r.site_xyz[3 * k] == p[0]);
    CHECK(std::abs(std::hypot(p[0], p[1], p[2]) - 1) < 0.05);  // on (the mesh of) the unit sphere
  }

  DeformRequest q;
  q.roi_seed = 10;
  q.roi_fraction = 0.2;
  q.handle_vertex = 10;
  q.handle_ring = 1;
  q.offset = {0.0, 0.0, 0.1};
  const DeformResult dr = s.deform(q);
  const DeformOperator op = prepare_deform_operator(m, DeformEnergy::Laplacian);
  const DeformRegion region = make_deform_region(vertex_adjacency(m), 10, 0.2, 10, 1);
  const DeformSystem sys = prepare_deform_system(op, region);
  Mesh out;
  solve_deformation(sys.sub.factor, sys, m, handle_target(m, region, q.offset), out);
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    CHECK(dr.xyz[3 * i] == out.x[i]);
    CHECK(dr.xyz[3 * i + 2] == out.z[i]);
  }
  CHECK(dr.roi_size == static_cast<int32_t>(region.roi.size()));
  CHECK(dr.xyz[3 * 10 + 2] == m.z[10] + 0.1);
  s.deform(q);
  CHECK(s.stats().deform_operators == 1);
}

TEST_CASE("session: concurrent queries from several threads equal single-threaded ones, factors built once") {
  const Mesh m = make_random_sphere(3000, 11);
  std::vector<std::vector<double>> want_d(4);
  std::vector<LogMapResult> want_l(4);
  std::vector<std::vector<double>> want_h(4);
  {
    const Session ref(m);
    for (int t = 0; t < 4; ++t) {
      want_d[t] = ref.geodesic_distance(100 * t + 1);
      want_l[t] = ref.logmap(200 * t + 7, 0.03);
      want_h[t] = ref.heat_values(std::vector<int32_t>{t, t + 10, t + 20}, std::vector<int32_t>{5, 6, 2999});
    }
  }
  const Session s(m);
  std::vector<std::vector<double>> got_d(4), got_h(4);
  std::vector<LogMapResult> got_l(4);
  std::vector<std::thread> th;
  std::atomic<int> failures{0};
  for (int t = 0; t < 4; ++t)
    th.emplace_back([&, t] {
      try {
        RunContext ctx;
        ctx.threads = 1 + t % 2;
        got_d[t] = s.geodesic_distance(100 * t + 1, {}, ctx);
        got_l[t] = s.logmap(200 * t + 7, 0.03, {}, ctx);
        got_h[t] = s.heat_values(std::vector<int32_t>{t, t + 10, t + 20}, std::vector<int32_t>{5, 6, 2999}, {}, ctx);
      } catch (...) {
        failures.fetch_add(1);
      }
    });
  for (auto& t : th) t.join();
  REQUIRE(failures.load() == 0);
  for (int t = 0; t < 4; ++t) {
    CHECK(got_d[t] == want_d[t]);
    CHECK(got_l[t].u == want_l[t].u);
    CHECK(got_l[t].v == want_l[t].v);
    CHECK(got_h[t] == want_h[t]);
  }
  const SessionStats st = s.stats();
  CHECK(st.heat_engines == 1);
  CHECK(st.numeric_factorizations == 1);
  CHECK(st.symbolic_analyses == 1);
}

TEST_CASE("session: bad meshes and bad arguments raise the right error; cancellation is not cached") {
  Mesh empty;
  CHECK(code_of([&] { Session s(empty); }) == ErrorCode::BadInput);
  Mesh no_faces;
  no_faces.add_vertex(0, 0, 0);
  CHECK(code_of([&] { Session s(no_faces); }) == ErrorCode::BadInput);
  Mesh unref = make_icosphere(1);
  unref.add_vertex(5, 5, 5);
  // An unreferenced vertex: refused by the cotan operator; auto runs on the robust one (NaN there).
  CHECK(code_of([&] { Session s(unref, SessionOptions{OperatorChoice::Cotan}); }) == ErrorCode::BadInput);
  CHECK(std::isnan(Session(unref).geodesic_distance(0).back()));
  Mesh nan = make_icosphere(1);
  nan.y[3] = NAN;
  CHECK(code_of([&] { Session s(nan); }) == ErrorCode::BadInput);
  Mesh out_of_range = make_icosphere(1);
  out_of_range.face_vertices[4] = 1000;
  out_of_range.rebuild_triangle_arrays();
  CHECK(code_of([&] { Session s(out_of_range); }) == ErrorCode::BadInput);
  CHECK(code_of([&] { Session::from_file("/nonexistent/file.off"); }) == ErrorCode::BadInput);

  const Session s(make_icosphere(2));
  const int32_t n = s.num_vertices();
  CHECK(code_of([&] { s.geodesic_distance(-1); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.geodesic_distance(n); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.geodesic_distance(0, HeatQuery{-1.0}); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.geodesic_distance(0, HeatQuery{NAN}); }) == ErrorCode::BadUsage);
  std::vector<double> small(3);
  CHECK(code_of([&] { s.geodesic_distance(0, small); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.logmap(0, 0.0); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.logmap(0, 1.5); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.logmap(0, NAN); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.cvt(0, 1, 1); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.cvt(n + 1, 1, 1); }) == ErrorCode::BadInput);  // depends on the mesh, as the command's
  CHECK(code_of([&] { s.cvt(3, -1, 1); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.heat_values(std::vector<int32_t>{0, n}, std::vector<int32_t>{1}); }) == ErrorCode::BadUsage);
  DeformRequest q;
  q.handle_vertex = n;
  CHECK(code_of([&] { s.deform(q); }) == ErrorCode::BadUsage);
  try {
    s.geodesic_distance(n + 5);
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find(std::to_string(n + 5)) != std::string::npos);
  }

  std::atomic<bool> cancel{true};
  RunContext ctx;
  ctx.cancel = &cancel;
  CHECK(code_of([&] { s.geodesic_distance(0, {}, ctx); }) == ErrorCode::Cancelled);
  CHECK(code_of([&] { s.heat_values(std::vector<int32_t>{1}, std::vector<int32_t>{2}, {}, ctx); }) ==
        ErrorCode::Cancelled);
  CHECK(s.stats().heat_engines == 0);
  const std::vector<double> d = s.geodesic_distance(0);  // the cancelled build was not cached
  CHECK(d[0] == 0.0);
  CHECK(s.stats().heat_engines == 1);
}

TEST_CASE("session: two components (distance NaN across, cvt and its remesh per component), one-vertex log-map patch") {
  Mesh m = make_icosphere(2);
  const Mesh other = make_icosphere(2);
  const int32_t n1 = m.num_vertices();
  for (int32_t i = 0; i < other.num_vertices(); ++i) m.add_vertex(other.x[i] + 5, other.y[i], other.z[i]);
  for (int32_t f = 0; f < other.num_faces(); ++f) m.add_triangle(other.f0[f] + n1, other.f1[f] + n1, other.f2[f] + n1);
  const Session s(m);
  const std::vector<double> d = s.geodesic_distance(3);
  int64_t no_value = 0;  // NaN: no path, no value (README "Output formats")
  for (int32_t i = n1; i < m.num_vertices(); ++i) no_value += std::isnan(d[i]);
  CHECK(no_value == m.num_vertices() - n1);
  for (int32_t i = 0; i < n1; ++i) CHECK(std::isfinite(d[i]));
  // cvt: random sites that miss a component are moved into it (every component
  // needs one), so both spheres get cells; one site for two components is refused.
  const CvtResult c = s.cvt(10, 1, 1);
  std::vector<int> cells_in(2, 0);
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    REQUIRE(c.label[v] >= 0);
    REQUIRE(c.label[v] < 10);
  }
  std::vector<int32_t> side(10, -1);  // every cell lies in one component
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const int32_t comp = v < n1 ? 0 : 1;
    if (side[c.label[v]] < 0) ++cells_in[comp];
    CHECK((side[c.label[v]] < 0 || side[c.label[v]] == comp));
    side[c.label[v]] = comp;
  }
  CHECK(cells_in[0] >= 1);
  CHECK(cells_in[1] >= 1);
  // One site for two components: raised to one per component.
  const CvtResult one_site = s.cvt(1, 1, 1);
  CHECK(one_site.site_xyz.size() == 6);
  CHECK(*std::max_element(one_site.label.begin(), one_site.label.end()) == 1);
  // The remesh of both: two spheres (chi = 4: F = 2V - 8), each vertex at its site.
  const CvtResult rm = s.cvt(80, 3, 2, {}, true);
  REQUIRE(rm.remeshed);
  const int64_t rv = static_cast<int64_t>(rm.remesh_xyz.size() / 3);
  CHECK(static_cast<int64_t>(rm.remesh_triangles.size() / 3) == 2 * rv - 8);
  CHECK(rm.remesh_components == 2);
  CHECK(rm.remesh_genus == 0);
  CHECK(rm.remesh_boundary_loops == 0);
  CHECK(rm.remesh_site.size() == static_cast<size_t>(rv));
  CHECK(rm.site_xyz.size() == 3 * (80 + static_cast<size_t>(rm.added_sites)));
  const LogMapResult r = s.logmap(n1 + 4, 0.5);  // the disk stays in the center's component
  for (int32_t v : r.patch) CHECK(v >= n1);

  const LogMapResult one = s.logmap(7, 1e-9);
  REQUIRE(one.patch.size() == 1);
  CHECK(one.patch[0] == 7);
  CHECK(one.u[0] == 0.0);
  CHECK(one.v[0] == 0.0);
}
