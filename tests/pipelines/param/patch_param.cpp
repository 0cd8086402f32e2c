// Tests for pipelines/patch_param and the patch grower (kernels/mesh/patch_grower) (thesis §4.4, eq. 4.6).
// Oracles: an Eigen SimplicialLDLT solve of the SAME global system
// (-L_C + eps M) [u v] = b, with b written out from eq. 4.6 here (independently
// of circle_neumann_rhs), read at the patch vertices; an independent BFS for
// the patch's vertex set; the analytic facts that a disk-like patch of a smooth
// sphere maps without flips and that eq. 4.6's data sum to zero over a loop.
#include "locus/pipelines/param/patch_param.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <cmath>
#include <deque>
#include <numbers>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

struct Global {
  CscMatrix K;
  NumericFactor F;
};

Global factor_laplacian(const Mesh& m) {
  Global g;
  g.K = regularized_laplacian(m);
  g.F = factorize(analyze(g.K, order_matrix(g.K)), g.K);
  return g;
}

// Graph distances from `c` (plain BFS, test-side).
std::vector<int32_t> bfs_distance(const Mesh& m, int32_t c) {
  const Adjacency adj = vertex_adjacency(m);
  std::vector<int32_t> d(m.num_vertices(), -1);
  std::deque<int32_t> q{c};
  d[c] = 0;
  while (!q.empty()) {
    const int32_t v = q.front();
    q.pop_front();
    for (int64_t k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k)
      if (d[adj.neighbors[k]] < 0) {
        d[adj.neighbors[k]] = d[v] + 1;
        q.push_back(adj.neighbors[k]);
      }
  }
  return d;
}

// Eq. 4.6 written out: circle by arc length, b = 1/2 (x_{j+1} - x_{j-1}) rotated clockwise.
Eigen::MatrixXd oracle_rhs(const Mesh& m, const std::vector<int32_t>& loop) {
  const size_t nb = loop.size();
  std::vector<double> s(nb + 1, 0.0);
  for (size_t j = 0; j < nb; ++j) {
    const int32_t a = loop[j], b = loop[(j + 1) % nb];
    s[j + 1] = s[j] + std::hypot(m.x[a] - m.x[b], m.y[a] - m.y[b], m.z[a] - m.z[b]);
  }
  const double r = s[nb] / (2 * std::numbers::pi);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(m.num_vertices(), 2);
  auto pos = [&](size_t j) {
    const double a = 2 * std::numbers::pi * s[j % nb] / s[nb];
    return Eigen::Vector2d(r * std::cos(a), r * std::sin(a));
  };
  for (size_t j = 0; j < nb; ++j) {
    const Eigen::Vector2d d = pos(j + 1) - pos(j + nb - 1);
    B(loop[j], 0) += 0.5 * d.y();
    B(loop[j], 1) += -0.5 * d.x();
  }
  return B;
}

void check_patch(const Mesh& m, int32_t center, double fraction, bool expect_disk) {
  const Global G = factor_laplacian(m);
  const PatchGrower grower = prepare_patch_grower(m);
  PatchWorkspace pws;
  SolveWorkspace ws;
  const int32_t count = patch_vertex_count(m.num_vertices(), fraction);
  const PatchParam P = parameterize_patch(G.F, grower, center, count, pws, ws);
  const size_t np = P.patch.vertices.size();
  REQUIRE(np > 10);

  // The patch is a BFS ball: every vertex closer than the last ring is in it, none farther.
  const std::vector<int32_t> d = bfs_distance(m, center);
  std::vector<uint8_t> in(m.num_vertices(), 0);
  for (int32_t v : P.patch.vertices) in[v] = 1;
  int64_t missing_inner = 0, too_far = 0;
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    if (d[v] >= 0 && d[v] < P.patch.rings - 1 && !in[v]) ++missing_inner;
    if (in[v] && d[v] > P.patch.rings) ++too_far;
  }
  CHECK(missing_inner == 0);
  CHECK(too_far == 0);
  CHECK(static_cast<int32_t>(np) <= count);
  CHECK(P.patch.vertices[0] == center);
  CHECK(ws.x.size() >= static_cast<size_t>(m.num_vertices()));
  CHECK(std::all_of(ws.x.begin(), ws.x.end(), [](double v) { return v == 0.0; }));

  // Same global system solved by Eigen, at the patch vertices.
  const Eigen::MatrixXd B = oracle_rhs(m, P.boundary);
  CHECK(std::abs(B.col(0).sum()) <= 1e-12 * B.col(0).cwiseAbs().sum());  // eq. 4.6 sums to zero over a closed loop
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(test::to_eigen(G.K));
  REQUIRE(ldlt.info() == Eigen::Success);
  const Eigen::MatrixXd X = ldlt.solve(B);
  double worst = 0, scale = 0;
  for (size_t k = 0; k < np; ++k)
    for (int c = 0; c < 2; ++c) {
      worst = std::max(worst, std::abs(P.uv_raw[2 * k + c] - X(P.patch.vertices[k], c)));
      scale = std::max(scale, std::abs(X(P.patch.vertices[k], c)));
    }
  // The regularized Laplacian has condition ~1e8 (mesh_operators.hpp), so two
  // different factorizations agree to ~1e-8 relative, not to machine precision.
  CHECK(worst <= 1e-7 * scale);

  // Normalized: centered, farthest vertex at radius 1.
  double cu = 0, cv = 0, rmax = 0;
  for (size_t k = 0; k < np; ++k) {
    cu += P.uv[2 * k];
    cv += P.uv[2 * k + 1];
    rmax = std::max(rmax, std::hypot(P.uv[2 * k], P.uv[2 * k + 1]));
  }
  CHECK(std::abs(cu / np) <= 1e-12);
  CHECK(std::abs(cv / np) <= 1e-12);
  CHECK(rmax == doctest::Approx(1.0).epsilon(1e-12));
  if (expect_disk) {
    CHECK(P.boundary_loops == 1);
    CHECK(P.euler_characteristic == 1);
    CHECK(P.flips.flipped == 0);
    CHECK(P.flips.degenerate == 0);
    CHECK(P.flips.orientation == 1);  // the loop follows the faces, the circle runs counter-clockwise
  }
}

}  // namespace

TEST_CASE("patch parameterization: global subset solve equals an Eigen solve, no flips on disk-like patches") {
  SUBCASE("icosphere, 10%") { check_patch(make_icosphere(4), 0, 0.10, true); }
  SUBCASE("icosphere, 40%, another center") { check_patch(make_icosphere(4), 1234, 0.40, true); }
  SUBCASE("torus, 5% (disk-like)") { check_patch(make_torus(80, 30), 17, 0.05, true); }
  SUBCASE("random sphere, 20%") { check_patch(make_random_sphere(3000, 5), 3, 0.20, false); }
}

TEST_CASE("patch parameterization: flip counter and normalization on hand-made data") {
  Mesh m;
  m.add_vertex(0, 0, 0);
  m.add_vertex(1, 0, 0);
  m.add_vertex(0, 1, 0);
  m.add_vertex(1, 1, 0);
  m.add_triangle(0, 1, 2);
  m.add_triangle(1, 3, 2);
  std::vector<double> uv{0, 0, 1, 0, 0, 1, 1, 1};
  UvFlips f = count_uv_flips(m, uv);
  CHECK(f.flipped == 0);
  CHECK(f.orientation == 1);
  uv[6] = -1;  // vertex 3 folded over the diagonal: face 1 turns clockwise
  uv[7] = -1;
  f = count_uv_flips(m, uv);
  CHECK(f.flipped == 1);
  uv = {0, 0, 1, 0, 0, 1, 0.5, 0.5};  // vertex 3 on the diagonal: degenerate
  f = count_uv_flips(m, uv);
  CHECK(f.degenerate == 1);
  CHECK(f.flipped == 0);
  std::vector<double> p{2, 2, 4, 2, 2, 4, 4, 4};
  normalize_uv(p);
  CHECK(p[0] == doctest::Approx(-std::sqrt(0.5)));
  CHECK(p[7] == doctest::Approx(std::sqrt(0.5)));
}

TEST_CASE("patch parameterization: bad input") {
  const Mesh m = make_icosphere(2);
  const Global G = factor_laplacian(m);
  const PatchGrower grower = prepare_patch_grower(m);
  PatchWorkspace pws;
  SolveWorkspace ws;
  CHECK_THROWS_AS(patch_vertex_count(100, 0.0), Error);
  CHECK_THROWS_AS(patch_vertex_count(100, 1.5), Error);
  CHECK_THROWS_AS(parameterize_patch(G.F, grower, -1, 10, pws, ws), Error);
  CHECK_THROWS_AS(parameterize_patch(G.F, grower, m.num_vertices(), 10, pws, ws), Error);
  // The whole sphere has no boundary: a clear BadInput, not a singular solve.
  try {
    parameterize_patch(G.F, grower, 0, m.num_vertices(), pws, ws);
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadInput);
    CHECK(std::string(e.what()).find("no boundary") != std::string::npos);
  }
  // The workspace is clean after the failures (no stale marks).
  CHECK(std::all_of(pws.local.begin(), pws.local.end(), [](int32_t v) { return v == -1; }));
  const Global other = factor_laplacian(make_icosphere(1));
  CHECK_THROWS_AS(parameterize_patch(other.F, grower, 0, 10, pws, ws), Error);
}
