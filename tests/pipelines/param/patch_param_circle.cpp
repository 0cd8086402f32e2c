// Tests for pipelines/patch_param_circle: the circle-boundary harmonic map of a
// disk patch with K_II's factor from the factor-once update.
// Oracles: the harmonic map assembled HERE from the cotan formula on the patch
// mesh (pure -L_C, no regularization), the boundary laid out here by arc
// length, solved by Eigen's SimplicialLDLT; a from-scratch factorization of
// K_II for the same system; topology facts (one loop, Euler characteristic 1).
#include "locus/pipelines/param/patch_param_circle.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"

using namespace locus;

namespace {

struct Global {
  const Mesh& m;
  CscMatrix K;
  NumericFactor F;
  PatchGrower g;
  explicit Global(const Mesh& mesh)
      : m(mesh), K(regularized_laplacian(mesh)), F(factorize(analyze(K, order_matrix(K)), K)),
        g(prepare_patch_grower(mesh)) {}
};

double cot_at(const Mesh& m, int32_t a, int32_t b, int32_t c) {  // angle at a of triangle (a, b, c)
  const double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], uz = m.z[b] - m.z[a];
  const double vx = m.x[c] - m.x[a], vy = m.y[c] - m.y[a], vz = m.z[c] - m.z[a];
  const double dot = ux * vx + uy * vy + uz * vz;
  const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
  return dot / std::sqrt(cx * cx + cy * cy + cz * cz);
}

// The harmonic map of the patch mesh pm with the loop (patch-local ids) on a
// circle of the loop's circumference, by arc length: uv of every patch vertex.
Eigen::MatrixXd oracle_map(const Mesh& pm, const std::vector<int32_t>& loop) {
  const int32_t np = pm.num_vertices();
  std::vector<int32_t> local(np, -1);
  const size_t nb = loop.size();
  double total = 0;
  std::vector<double> arc(nb);
  for (size_t j = 0; j < nb; ++j) {
    arc[j] = total;
    const int32_t a = loop[j], b = loop[(j + 1) % nb];
    total += std::sqrt((pm.x[a] - pm.x[b]) * (pm.x[a] - pm.x[b]) + (pm.y[a] - pm.y[b]) * (pm.y[a] - pm.y[b]) +
                       (pm.z[a] - pm.z[b]) * (pm.z[a] - pm.z[b]));
  }
  Eigen::MatrixXd uv(np, 2);
  std::vector<char> fixed(np, 0);
  for (size_t j = 0; j < nb; ++j) {
    const double ang = 2 * std::numbers::pi * arc[j] / total, r = total / (2 * std::numbers::pi);
    uv(loop[j], 0) = r * std::cos(ang);
    uv(loop[j], 1) = r * std::sin(ang);
    fixed[loop[j]] = 1;
  }
  int32_t ni = 0;
  for (int32_t v = 0; v < np; ++v)
    if (!fixed[v]) local[v] = ni++;
  std::vector<Eigen::Triplet<double>> t;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(ni, 2);
  auto edge = [&](int32_t i, int32_t j, double w) {  // adds w (u_i - u_j)^2 / 2 to the energy
    if (local[i] >= 0) {
      t.emplace_back(local[i], local[i], w);
      if (local[j] >= 0) t.emplace_back(local[i], local[j], -w);
      else b.row(local[i]) += w * uv.row(j);
    }
  };
  for (int32_t f = 0; f < pm.num_faces(); ++f) {
    const int32_t a = pm.f0[f], bb = pm.f1[f], c = pm.f2[f];
    const double wa = 0.5 * cot_at(pm, a, bb, c), wb = 0.5 * cot_at(pm, bb, c, a), wc = 0.5 * cot_at(pm, c, a, bb);
    edge(bb, c, wa), edge(c, bb, wa);
    edge(c, a, wb), edge(a, c, wb);
    edge(a, bb, wc), edge(bb, a, wc);
  }
  Eigen::SparseMatrix<double> L(ni, ni);
  L.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(L);
  REQUIRE(ldlt.info() == Eigen::Success);
  const Eigen::MatrixXd x = ldlt.solve(b);
  for (int32_t v = 0; v < np; ++v)
    if (local[v] >= 0) uv.row(v) = x.row(local[v]);
  return uv;
}

void check_map(const Mesh& m, int32_t center, double fraction, bool expect_no_flips) {
  CAPTURE(center);
  CAPTURE(fraction);
  Global G(m);
  CirclePatchParameterizer cp(G.F, G.K, G.g);
  const CirclePatchParam P = cp.parameterize(center, patch_vertex_count(m.num_vertices(), fraction));
  const Mesh& pm = P.disk.patch.mesh;
  const size_t np = P.disk.patch.vertices.size();
  REQUIRE(P.uv_raw.size() == 2 * np);
  // A disk: one boundary loop, Euler characteristic 1 (counted independently).
  const std::vector<std::vector<int32_t>> loops = boundary_loops(pm);
  REQUIRE(loops.size() == 1);
  CHECK(P.disk.euler_characteristic == 1);
  CHECK(static_cast<int64_t>(np) - static_cast<int64_t>(unique_edges(pm).e0.size()) + pm.num_faces() == 1);
  CHECK(P.interior == static_cast<int32_t>(np - P.disk.boundary.size()));
  CHECK(P.refinement_steps >= 1);

  // The harmonic map (pure cotan Laplacian, Dirichlet circle) by Eigen.
  const Eigen::MatrixXd X = oracle_map(pm, P.disk.boundary_local);
  double worst = 0, scale = 0;
  for (size_t k = 0; k < np; ++k)
    for (int c = 0; c < 2; ++c) {
      worst = std::max(worst, std::abs(P.uv_raw[2 * k + c] - X(static_cast<Eigen::Index>(k), c)));
      scale = std::max(scale, std::abs(X(static_cast<Eigen::Index>(k), c)));
    }
  CHECK(worst <= 1e-9 * scale);

  // The same system factored from scratch gives the same map.
  DiskPatchWorkspace ws;
  const DiskPatch d = grow_disk_patch(G.g, center, patch_vertex_count(m.num_vertices(), fraction), ws);
  REQUIRE(d.patch.vertices == P.disk.patch.vertices);
  const CircleDirichletSystem sys = circle_dirichlet_system(G.K, d, ws);
  CHECK(std::all_of(ws.mark.begin(), ws.mark.end(), [](int32_t v) { return v == -1; }));
  const CscMatrix Kii = principal_submatrix(G.K, sys.interior);
  const NumericFactor Fii = factorize(analyze(Kii, order_matrix(Kii)), Kii);
  std::vector<double> uv_int(2 * sys.interior.size());
  solve_circle_dirichlet(Fii, Kii, sys, uv_int);
  const std::vector<double> uv = assemble_patch_uv(d, sys, uv_int);
  double diff = 0;
  for (size_t k = 0; k < uv.size(); ++k) diff = std::max(diff, std::abs(uv[k] - P.uv_raw[k]));
  CHECK(diff <= 1e-10 * scale);

  if (expect_no_flips) {
    CHECK(P.flips.flipped == 0);
    CHECK(P.flips.degenerate == 0);
    CHECK(P.flips.orientation == 1);
  }
}

}  // namespace

TEST_CASE("circle patch map: harmonic map with the circle boundary equals an Eigen solve, no flips") {
  SUBCASE("icosphere, 10%") { check_map(make_icosphere(4), 0, 0.10, true); }
  SUBCASE("icosphere, 40%") { check_map(make_icosphere(4), 1234, 0.40, true); }
  SUBCASE("torus, 5%") { check_map(make_torus(80, 30), 17, 0.05, true); }
  // Thin triangles have negative cotan weights: flips are possible there.
  SUBCASE("random sphere, 20%") { check_map(make_random_sphere(3000, 5), 3, 0.20, false); }
}

TEST_CASE("circle patch map: holes of the BFS patch are filled") {
  const Mesh m = make_random_sphere(4000, 11);
  const PatchGrower g = prepare_patch_grower(m);
  DiskPatchWorkspace ws;
  PatchWorkspace pws;
  int with_holes = 0;
  for (int32_t count = 40; count <= 1200; count += 23) {
    CAPTURE(count);
    const MeshPatch bfs = grow_patch(g, 7, ring_patch(count), pws);
    const size_t bfs_loops = boundary_loops(bfs.mesh).size();
    DiskPatch d;
    try {
      d = grow_disk_patch(g, 7, count, ws);
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::BadInput);  // a hole reaching the outside: refused, never a wrong patch
      continue;
    }
    CHECK(std::all_of(ws.mark.begin(), ws.mark.end(), [](int32_t v) { return v == -1; }));
    CHECK(boundary_loops(d.patch.mesh).size() == 1);
    CHECK(d.euler_characteristic == 1);
    // Every BFS vertex is kept; the added ones are new.
    std::vector<int32_t> a = bfs.vertices, b = d.patch.vertices;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    CHECK(std::includes(b.begin(), b.end(), a.begin(), a.end()));
    CHECK(b.size() == a.size() + static_cast<size_t>(d.vertices_added));
    CHECK(d.holes_filled == static_cast<int32_t>(bfs_loops) - 1);
    if (d.holes_filled > 0) ++with_holes;
  }
  MESSAGE("patches with filled holes: " << with_holes);
  CHECK(with_holes > 0);  // the sweep must exercise the filling
}

TEST_CASE("circle patch map: refusals") {
  const Mesh m = make_icosphere(3);
  Global G(m);
  CirclePatchParameterizer cp(G.F, G.K, G.g);
  // The whole sphere: no boundary.
  CHECK_THROWS_AS(cp.parameterize(0, m.num_vertices()), Error);
  // Three vertices around a valence-5/6 center hold no whole face once the
  // partial ring's ears are dropped.
  try {
    cp.parameterize(0, 3);
    FAIL("expected BadInput");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadInput);
    CAPTURE(std::string(e.what()));
    CHECK(std::string(e.what()).find("no whole face") != std::string::npos);
  }
  // The parameterizer still works after refusals (its maps were reset).
  const CirclePatchParam P = cp.parameterize(5, 100);
  CHECK(P.flips.flipped == 0);
  // A factor of another mesh is refused.
  const Mesh other = make_icosphere(2);
  Global O(other);
  CHECK_THROWS_AS(CirclePatchParameterizer(O.F, O.K, G.g), Error);
}
