// Tests for the Session queries of the diffusion, shape and Voronoi pipelines
// (engine/src/session_{heat,voronoi,param,laplacian}.cpp).
// Oracles: Eigen sparse LDLT solves of M - tL for the auto-diffusion function,
// the Voronoi labels (hottest generator),
// the heat kernel signature and the heat exchange (entries of the inverse);
// the pipeline functions called directly on freshly prepared operators (the
// Session must reproduce them bit for bit, whatever it cached before); the
// defining properties of natural-neighbor coordinates and skinning weights
// (non-negative, partition of unity, indicator at a site); and the Session's
// counters for "one factorization per t serves every diffusion pipeline".
#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <thread>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/pipelines/laplacian/flipfree_param.hpp"
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"
#include "locus/pipelines/laplacian/self_supporting.hpp"
#include "locus/pipelines/param/patch_param.hpp"
#include "locus/pipelines/param/patch_param_circle.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"
#include "locus/session.hpp"
#include "tests/kernels/matrix_fixtures.hpp"
#include "tests/engine/session_test_support.hpp"

using namespace locus;
using SpMat = Eigen::SparseMatrix<double>;
using locus::test::code_of;
using locus::test::to_eigen;

namespace {

// The column of (M - t L)^{-1} for the right-hand side b, by Eigen.
Eigen::VectorXd heat_solve(const Mesh& m, double t, const Eigen::VectorXd& b) {
  Eigen::SimplicialLDLT<SpMat> ldlt(to_eigen(heat_operator(m, t)));
  REQUIRE(ldlt.info() == Eigen::Success);
  return ldlt.solve(b);
}

SurfacePoint kernel_point(const MeshPoint& p) { return SurfacePoint{p.face, p.face < 0 ? p.vertex : -1, p.bary}; }

std::vector<SurfacePoint> kernel_points(const std::vector<MeshPoint>& p) {
  std::vector<SurfacePoint> out;
  for (const MeshPoint& q : p) out.push_back(kernel_point(q));
  return out;
}

}  // namespace

TEST_CASE("session ADF, HKS and heat exchange: entries of (M - tL)^{-1} by Eigen; one factor per t") {
  const Mesh m = make_icosphere(3);
  const Session s(m);
  const int32_t n = m.num_vertices();
  const double h = s.mean_edge_length();
  const std::vector<int32_t> verts{0, 5, 77, 300, 641};
  const std::vector<double> adf = s.auto_diffusion(verts);
  for (size_t k = 0; k < verts.size(); ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e[verts[k]] = 1;
    CHECK(adf[k] == doctest::Approx(heat_solve(m, h * h, e)[verts[k]]).epsilon(1e-11));
  }
  // All vertices: subset walks and selected inversion agree.
  const std::vector<double> all = s.auto_diffusion({});
  const std::vector<double> all_selinv = s.auto_diffusion({}, {}, DiagonalMethod::SelectedInversion);
  REQUIRE(all.size() == static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) CHECK(all_selinv[i] == doctest::Approx(all[i]).epsilon(1e-10));
  for (size_t k = 0; k < verts.size(); ++k) CHECK(all[verts[k]] == adf[k]);

  // HKS over three times (one absolute): column j is the ADF at t_j.
  const std::vector<HeatQuery> times{HeatQuery{1.0, 0.0}, HeatQuery{10.0, 0.0}, HeatQuery{1.0, 0.5 * h * h}};
  const std::vector<double> hks = s.heat_kernel_signature(times, verts);
  for (size_t j = 0; j < times.size(); ++j) {
    const std::vector<double> col = s.auto_diffusion(verts, times[j]);
    for (size_t k = 0; k < verts.size(); ++k) CHECK(hks[k * times.size() + j] == col[k]);
  }
  for (size_t k = 0; k < verts.size(); ++k) CHECK(hks[k * 3 + 1] < hks[k * 3]);  // ADF decreases in t

  // Heat exchange: sum over sources (repeats add) of the columns, read at the targets.
  const std::vector<int32_t> src{3, 9, 9}, tgt{100, 3, 600};
  const std::vector<double> hx = s.heat_exchange(src, tgt);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (int32_t v : src) b[v] += 1;
  const Eigen::VectorXd x = heat_solve(m, h * h, b);
  for (size_t k = 0; k < tgt.size(); ++k) CHECK(hx[k] == doctest::Approx(x[tgt[k]]).epsilon(1e-11));
  // t = h^2, 10 h^2 and 0.5 h^2: three factorizations, whatever else was asked.
  CHECK(s.stats().numeric_factorizations == 3);
  const std::vector<double> hv = s.heat_values(src, tgt);  // per-source values, on the same cached factor
  CHECK(hv[0] + hv[3] + hv[6] == doctest::Approx(hx[0]).epsilon(1e-12));
  CHECK(s.stats().numeric_factorizations == 3);

  CHECK(code_of([&] { s.auto_diffusion(std::vector<int32_t>{n}); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.heat_exchange({}, tgt); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.heat_exchange(src, std::vector<int32_t>{-1}); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.heat_kernel_signature({}, verts); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.auto_diffusion(verts, HeatQuery{1.0, -1.0}); }) == ErrorCode::BadUsage);
}

TEST_CASE("session Voronoi, natural neighbors and skinning weights: the pipelines' numbers; properties") {
  const Mesh m = make_icosphere(3);
  const Session s(m);
  const int32_t n = m.num_vertices();
  const std::vector<MeshPoint> sites{MeshPoint::at_vertex(0), MeshPoint::at_vertex(100), MeshPoint::at_vertex(400),
                                     MeshPoint::in_face(900, 0.3, 0.3, 0.4), MeshPoint::at_vertex(600)};
  const std::vector<SurfacePoint> ks = kernel_points(sites);
  const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, {});

  const VoronoiResult V = s.voronoi(sites);
  const HeatVoronoi PV = heat_voronoi(H, m, ks, {}, {}, {});
  const VoronoiDiagram PD = extract_voronoi_diagram(H, m, ks, PV, {});
  CHECK(V.label == PV.label);
  CHECK(V.points == PD.points);
  REQUIRE(V.line_offsets.size() == PD.polylines.size() + 1);
  for (size_t k = 0; k < PD.polylines.size(); ++k)
    CHECK(std::vector<int32_t>(V.line_points.begin() + V.line_offsets[k], V.line_points.begin() + V.line_offsets[k + 1]) ==
          PD.polylines[k]);
  CHECK(V.corners == PD.corners);
  CHECK(V.corners > 0);
  for (int32_t g : {0, 1, 2, 4}) CHECK(V.label[sites[g].vertex] == g);  // a vertex generator is in its own cell
  // Independent oracle for the labels: the hottest generator by Eigen solves of (M - h^2 L) u = b(generator).
  {
    const double h = s.mean_edge_length();
    std::vector<Eigen::VectorXd> heat;
    for (const MeshPoint& p : sites) {
      Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
      if (p.face < 0) b[p.vertex] = 1;
      else {
        b[m.f0[p.face]] = p.bary[0];
        b[m.f1[p.face]] = p.bary[1];
        b[m.f2[p.face]] = p.bary[2];
      }
      heat.push_back(heat_solve(m, h * h, b));
    }
    int64_t differ = 0;
    for (int32_t v = 0; v < n; ++v) {
      int32_t best = 0;
      for (int32_t g = 1; g < static_cast<int32_t>(sites.size()); ++g)
        if (heat[g][v] > heat[best][v]) best = g;
      differ += best != V.label[v];
    }
    CHECK(differ == 0);
  }
  CHECK(V.empty_cells == 0);

  // Natural neighbors: the prepared field reproduces the pipeline, from several threads at once.
  const NaturalNeighbors F = s.prepare_natural_neighbors(sites);
  CHECK(F.num_sites() == 5);
  const NaturalNeighborField PF = prepare_natural_neighbors(H, m, ks, {});
  std::vector<MeshPoint> queries;
  for (int32_t f = 0; f < m.num_faces(); f += 97) queries.push_back(MeshPoint::in_face(f, 0.2, 0.5, 0.3));
  std::vector<NaturalNeighborResult> r1(queries.size()), r2(queries.size());
  std::thread a([&] { for (size_t k = 0; k < queries.size(); ++k) r1[k] = F.coordinates(queries[k]); });
  std::thread b([&] { for (size_t k = 0; k < queries.size(); ++k) r2[k] = F.coordinates(queries[k]); });
  a.join();
  b.join();
  for (size_t k = 0; k < queries.size(); ++k) {
    const NaturalCoordinates c = natural_neighbor_coordinates(PF, m, kernel_point(queries[k]));
    CHECK(r1[k].weight == c.weight);
    CHECK(r2[k].weight == c.weight);
    double sum = 0;
    for (double w : c.weight) {
      CHECK(w >= 0.0);
      sum += w;
    }
    CHECK(sum == doctest::Approx(1.0).epsilon(1e-9));
  }
  const NaturalNeighborResult at = s.natural_neighbor_coordinates(sites, MeshPoint::at_vertex(100));
  CHECK(at.weight == std::vector<double>{0, 1, 0, 0, 0});
  CHECK(code_of([&] { F.coordinates(MeshPoint::in_face(m.num_faces(), 1, 0, 0)); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.natural_neighbor_coordinates(sites, MeshPoint::at_vertex(n)); }) == ErrorCode::BadUsage);

  // Skinning weights of three handles.
  const std::vector<MeshPoint> handles{MeshPoint::at_vertex(0), MeshPoint::at_vertex(300), MeshPoint::at_vertex(641)};
  const SkinningWeightsResult W = s.skinning_weights(handles);
  const SkinningWeights PW = skinning_weights(H, m, kernel_points(handles), {});
  CHECK(W.weight == PW.weight);
  REQUIRE(W.weight.size() == 3 * static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v)
    CHECK(W.weight[3 * v] + W.weight[3 * v + 1] + W.weight[3 * v + 2] == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(W.weight[3 * 300 + 1] == 1.0);
  CHECK(s.stats().numeric_factorizations == 1);  // one factor of M - h^2 L served all three

  CHECK(code_of([&] { s.voronoi(std::vector<MeshPoint>{}); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.skinning_weights(std::vector<MeshPoint>{MeshPoint::in_face(0, 2, -1, 0)}); }) ==
        ErrorCode::BadUsage);
}

TEST_CASE("session patch parameterization: the pipelines on a fresh factor of -L + eps M, bit for bit") {
  const Mesh m = make_icosphere(4);
  const Session s(m);
  const CscMatrix K = regularized_laplacian(m);
  const NumericFactor F = factorize(analyze(K, order_matrix(K)), K, {});
  const PatchGrower g = prepare_patch_grower(m);
  for (PatchBoundary b : {PatchBoundary::Neumann, PatchBoundary::Circle}) {
    for (int32_t center : {0, 1234}) {
      const PatchParamResult r = s.parameterize_patch({center, 0.05, b});
      const int32_t count = patch_vertex_count(m.num_vertices(), 0.05);
      std::vector<double> uv;
      std::vector<int32_t> verts;
      if (b == PatchBoundary::Neumann) {
        PatchWorkspace pws;
        SolveWorkspace ws;
        const PatchParam P = parameterize_patch(F, g, center, count, pws, ws);
        uv = P.uv;
        verts = P.patch.vertices;
      } else {
        CirclePatchParameterizer cp(F, K, g);
        const CirclePatchParam P = cp.parameterize(center, count);
        uv = P.uv;
        verts = P.disk.patch.vertices;
      }
      CHECK(r.uv == uv);
      CHECK(r.vertices == verts);
      CHECK(r.vertices[0] == center);
      CHECK(r.triangles.size() % 3 == 0);
      CHECK(r.flipped_faces == 0);
    }
  }
  CHECK(s.stats().numeric_factorizations == 1);
  CHECK(code_of([&] { s.parameterize_patch({m.num_vertices(), 0.1, PatchBoundary::Neumann}); }) == ErrorCode::BadUsage);
  CHECK(code_of([&] { s.parameterize_patch({0, 0.0, PatchBoundary::Neumann}); }) == ErrorCode::BadUsage);
}

TEST_CASE("session disk parameterization, perfect Laplacian and self-supporting surface: the pipelines' numbers") {
  Mesh m = make_disk(5, 0.3, 7);
  for (int32_t v = 0; v < m.num_vertices(); ++v) m.z[v] = 0.4 * (1 - m.x[v] * m.x[v] - m.y[v] * m.y[v]);
  const Session s(m);
  for (DiskParamMethod method : {DiskParamMethod::Perfect, DiskParamMethod::Cotan, DiskParamMethod::Uniform}) {
    const DiskParamResult r = s.parameterize_disk({method, 200, 1e-6});
    FlipFreeParamOptions o;
    o.method = method == DiskParamMethod::Cotan     ? ParamMethod::Cotan
               : method == DiskParamMethod::Uniform ? ParamMethod::Uniform
                                                    : ParamMethod::Perfect;
    o.iteration.max_iterations = 200;
    const FlipFreeParamResult p = flipfree_param(m, o);
    CHECK(r.uv == p.uv);
    CHECK(r.flipped_faces == p.faces.flipped_faces);
    if (method != DiskParamMethod::Cotan) CHECK(r.flipped_faces == 0);
  }

  const PerfectLaplacianOutput pl = s.perfect_laplacian({false, 200, 1e-6, true});
  MeshPerfectLaplacianOptions po;
  po.iteration.max_iterations = 200;
  const MeshPerfectLaplacianResult P = perfect_laplacian(m, po);
  CHECK(pl.weights == P.run.weights);
  REQUIRE(pl.edges.size() == 2 * P.e0.size());
  CHECK(static_cast<int64_t>(P.e0.size()) == s.num_edges());
  for (size_t e = 0; e < P.e0.size(); ++e) {
    CHECK(pl.edges[2 * e] == P.e0[e]);
    CHECK(pl.edges[2 * e + 1] == P.e1[e]);
  }
  for (int32_t i = 0; i < m.num_vertices(); ++i)
    for (int c = 0; c < 3; ++c) CHECK(pl.xyz[3 * i + c] == P.aligned[c][i]);
  CHECK(pl.converged == P.run.converged);

  const SelfSupportOutput ss = s.self_supporting({1.0, 100, 1e-6});
  SelfSupportOptions so;
  so.iteration.max_iterations = 100;
  const SelfSupportResult S = self_supporting(m, so);
  CHECK(ss.forces == S.forces);
  for (int32_t i = 0; i < m.num_vertices(); ++i)
    for (int c = 0; c < 3; ++c) CHECK(ss.xyz[3 * i + c] == S.pos[c][i]);
  for (double f : ss.forces) CHECK(f >= 0.0);
  CHECK(ss.residual_rel < 1e-8);  // every iterate is an equilibrium of its own forces

  const Session closed(make_icosphere(1));
  CHECK(code_of([&] { closed.parameterize_disk(); }) == ErrorCode::BadInput);
  CHECK(code_of([&] { closed.self_supporting(); }) == ErrorCode::BadInput);
  CHECK(code_of([&] { s.perfect_laplacian({false, 0, 1e-6, true}); }) == ErrorCode::BadUsage);
}

TEST_CASE("session pipelines from several threads at once: the single-threaded answers; cancellation is not cached") {
  const Mesh m = make_icosphere(3);
  const std::vector<MeshPoint> sites{MeshPoint::at_vertex(1), MeshPoint::at_vertex(200), MeshPoint::at_vertex(500)};
  const std::vector<int32_t> verts{0, 33, 400};
  const std::vector<HeatQuery> times{HeatQuery{1.0, 0.0}, HeatQuery{4.0, 0.0}};
  // Reference answers, each from a fresh Session on one thread.
  const std::vector<double> geo = Session(m).geodesic_distance(sites);
  const std::vector<int32_t> labels = Session(m).voronoi(sites).label;
  const std::vector<double> hks = Session(m).heat_kernel_signature(times, verts);
  const std::vector<double> uv = Session(m).parameterize_patch({3, 0.1, PatchBoundary::Circle}).uv;

  const Session s(m);  // nothing cached: the threads race for the same factors
  std::atomic<int> wrong{0};
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k)
    threads.emplace_back([&, k] {
      for (int r = 0; r < 2; ++r) {
        switch ((k + r) % 4) {
          case 0: wrong += s.geodesic_distance(sites) != geo; break;
          case 1: wrong += s.voronoi(sites).label != labels; break;
          case 2: wrong += s.heat_kernel_signature(times, verts) != hks; break;
          default: wrong += s.parameterize_patch({3, 0.1, PatchBoundary::Circle}).uv != uv; break;
        }
      }
    });
  for (std::thread& t : threads) t.join();
  CHECK(wrong == 0);
  CHECK(s.stats().numeric_factorizations == 3);  // M - h^2 L, M - 4h^2 L, -L + eps M: each built once
  CHECK(s.stats().heat_engines == 1);

  // A cancelled build leaves the Session usable and caches nothing.
  const Session c(m);
  std::atomic<bool> cancel{true};
  RunContext ctx;
  ctx.cancel = &cancel;
  CHECK(code_of([&] { c.voronoi(sites, {}, ctx); }) == ErrorCode::Cancelled);
  CHECK(code_of([&] { c.heat_kernel_signature(times, verts, DiagonalMethod::Subset, ctx); }) == ErrorCode::Cancelled);
  CHECK(code_of([&] { c.parameterize_patch({3, 0.1, PatchBoundary::Neumann}, ctx); }) == ErrorCode::Cancelled);
  CHECK(c.voronoi(sites).label == labels);
  CHECK(c.heat_kernel_signature(times, verts) == hks);
}

TEST_CASE("one-shot chapter-2 pipelines on a quad mesh: the pipelines' numbers, also through a Session") {
  const int n = 8;
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
      m.add_vertex(x, y, 0.5 * (1 - x * x) * (1 - y * y) + 0.03 * std::sin(5 * x + 2 * y));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i;
      const int32_t q[4] = {a, a + 1, a + n + 2, a + n + 1};
      m.add_face(q);
    }
  const DiskParamResult d = parameterize_disk_of(m, {DiskParamMethod::Perfect, 200, 1e-6});
  FlipFreeParamOptions fo;
  fo.iteration.max_iterations = 200;
  CHECK(d.uv == flipfree_param(m, fo).uv);
  CHECK(d.flipped_faces == 0);

  const PerfectLaplacianOutput pl = perfect_laplacian_of(m, {false, 100, 1e-6, true});
  MeshPerfectLaplacianOptions po;
  po.iteration.max_iterations = 100;
  const MeshPerfectLaplacianResult P = perfect_laplacian(m, po);
  CHECK(pl.weights == P.run.weights);
  CHECK(pl.edges.size() == 2 * P.e0.size());
  CHECK(P.e0.size() == static_cast<size_t>(2 * n * (n + 1)));  // a quad grid's edges: no diagonals

  const SelfSupportOutput ss = self_supporting_of(m, {1.0, 50, 1e-6});
  SelfSupportOptions so;
  so.iteration.max_iterations = 50;
  CHECK(ss.forces == self_supporting(m, so).forces);
  // A Session on the quads runs these on the quads too (its other pipelines on their triangulation).
  const Session quads(m);
  CHECK(quads.parameterize_disk({DiskParamMethod::Perfect, 200, 1e-6}).uv == d.uv);
  CHECK(quads.perfect_laplacian({false, 100, 1e-6, true}).weights == pl.weights);
  CHECK(quads.self_supporting({1.0, 50, 1e-6}).forces == ss.forces);
}

TEST_CASE("session natural neighbors in the plane: linear precision up to the cells' discretization") {
  const Mesh m = make_grid(40);  // [0,1]^2, 1681 vertices
  const Session s(m);
  std::vector<MeshPoint> sites;
  for (int32_t j : {8, 20, 32})
    for (int32_t i : {8, 20, 32}) sites.push_back(MeshPoint::at_vertex(j * 41 + i));
  const NaturalNeighbors F = s.prepare_natural_neighbors(sites);
  double worst = 0;
  // Query points well inside the sites' convex hull [0.2, 0.8]^2 (outside it no coordinates have linear precision).
  for (int32_t f : {2 * (14 * 40 + 14), 2 * (16 * 40 + 22) + 1, 2 * (20 * 40 + 20), 2 * (24 * 40 + 17) + 1, 2 * (26 * 40 + 26)}) {
    const MeshPoint q = MeshPoint::in_face(f, 0.3, 0.3, 0.4);
    const double qx = 0.3 * m.x[m.f0[f]] + 0.3 * m.x[m.f1[f]] + 0.4 * m.x[m.f2[f]];
    const double qy = 0.3 * m.y[m.f0[f]] + 0.3 * m.y[m.f1[f]] + 0.4 * m.y[m.f2[f]];
    const NaturalNeighborResult r = F.coordinates(q);
    double x = 0, y = 0;
    for (size_t k = 0; k < sites.size(); ++k) {
      x += r.weight[k] * m.x[sites[k].vertex];
      y += r.weight[k] * m.y[sites[k].vertex];
    }
    worst = std::max(worst, std::hypot(x - qx, y - qy));
  }
  INFO("max |sum w_i p_i - q| = " << worst << " (site spacing 0.3, edge 0.025)");
  CHECK(worst < 0.0125);  // half an edge; 0.0032 measured
}
