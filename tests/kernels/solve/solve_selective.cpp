// Tests for kernels/solve_selective (pruned approximate selective solve, 8 lanes)
// and the kept-set part of kernels/solve_plan: each lane equals an independent
// dense evaluation of thesis Algorithm 2 (x_K = (L^T)_KK^{-1} (L^{-1} b)_K, from
// Eigen's own Cholesky factor), for compact patches (where the forward pruning
// skips most of the reach) and scattered sets; plans reused across calls equal
// fresh plans; the workspace is clean afterwards.
#include "locus/kernels/solve/solve_selective.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

// Vertices of the grid rectangle [x0, x1) x [y0, y1) of an nx-wide grid.
std::vector<int32_t> grid_patch(int nx, int x0, int x1, int y0, int y1) {
  std::vector<int32_t> p;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) p.push_back(y * nx + x);
  return p;
}

}  // namespace

TEST_CASE("pruned selective solve equals a dense Algorithm 2 in every lane; plans reused equal fresh plans") {
  const int nx = 48, ny = 40;
  const CscMatrix A = test::grid_laplacian(nx, ny, 0.05);
  auto S = analyze(A, order_matrix(A));
  const NumericFactor F = factorize(S, A);
  const int32_t n = F.n();
  // Independent L (factor numbering) from Eigen.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(n);
  for (int32_t k = 0; k < n; ++k) P.indices()[S->perm[k]] = k;
  const Eigen::SparseMatrix<double> E = test::to_eigen(A);
  const Eigen::SparseMatrix<double> PE = (P * E * P.transpose()).eval();
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(PE);
  const Eigen::MatrixXd L = Eigen::MatrixXd(Eigen::SparseMatrix<double>(llt.matrixL()));

  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  SolveWorkspace ws;
  SolvePlan plan;
  PlanWorkspace pws;
  struct Case {
    std::vector<int32_t> supp, kept;
  };
  std::vector<Case> cases;
  cases.push_back({grid_patch(nx, 5, 8, 5, 8), grid_patch(nx, 2, 12, 2, 12)});          // corner patch
  cases.push_back({grid_patch(nx, 22, 25, 18, 21), grid_patch(nx, 17, 30, 13, 26)});    // central patch
  cases.push_back({{0}, {0}});                                                           // single entry
  {
    std::vector<int32_t> all(n), few;
    for (int32_t i = 0; i < n; ++i) all[i] = i;
    std::shuffle(all.begin(), all.end(), rng);
    few.assign(all.begin(), all.begin() + 5);
    std::vector<int32_t> many(all.begin(), all.begin() + 300);
    many.insert(many.end(), many.begin(), many.begin() + 20);  // repeated kept ids are allowed
    many.push_back(few[0]);
    cases.push_back({few, many});                                                        // scattered
    std::vector<int32_t> every(n);
    for (int32_t i = 0; i < n; ++i) every[i] = i;
    cases.push_back({few, every});                                                       // everything: exact
  }
  int pruned_cases = 0;
  for (size_t ci = 0; ci < cases.size(); ++ci) {
    CAPTURE(ci);
    const Case& c = cases[ci];
    plan_selective_solve(*S, c.supp, c.kept, plan, pws);
    const SolvePlan fresh = plan_selective_solve(*S, c.supp, c.kept);
    CHECK(plan.forward == fresh.forward);
    CHECK(plan.backward == fresh.backward);
    CHECK(plan.kept_cols == fresh.kept_cols);
    CHECK(plan.forward_pruned == fresh.forward_pruned);
    CHECK(std::is_sorted(plan.kept_cols.begin(), plan.kept_cols.end()));
    CHECK(std::includes(plan.forward.begin(), plan.forward.end(), plan.forward_pruned.begin(), plan.forward_pruned.end()));
    pruned_cases += plan.forward_pruned.size() < plan.forward.size();
    CHECK(std::all_of(pws.seen.begin(), pws.seen.end(), [](uint8_t v) { return v == 0; }));
    CHECK(std::all_of(pws.col_seen.begin(), pws.col_seen.end(), [](uint8_t v) { return v == 0; }));

    std::vector<double> rhs(c.supp.size() * kLanes), out(c.kept.size() * kLanes);
    for (auto& v : rhs) v = u(rng);
    solve_selective8(F, plan, rhs, out, ws);
    CHECK(std::all_of(ws.x.begin(), ws.x.end(), [](double v) { return v == 0.0; }));
    CHECK(std::all_of(ws.keep.begin(), ws.keep.end(), [](uint8_t v) { return v == 0; }));

    std::vector<int32_t> K;
    for (int32_t v : c.kept) K.push_back(S->iperm[v]);
    std::sort(K.begin(), K.end());
    K.erase(std::unique(K.begin(), K.end()), K.end());
    CHECK(K == plan.kept_cols);
    const int kk = static_cast<int>(K.size());
    Eigen::MatrixXd LKK(kk, kk);
    for (int a = 0; a < kk; ++a)
      for (int b = 0; b < kk; ++b) LKK(a, b) = L(K[a], K[b]);
    for (int lane = 0; lane < kLanes; ++lane) {
      Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
      for (size_t k = 0; k < c.supp.size(); ++k) b[S->iperm[c.supp[k]]] += rhs[k * kLanes + lane];
      const Eigen::VectorXd y = L.triangularView<Eigen::Lower>().solve(b);
      Eigen::VectorXd yK(kk);
      for (int a = 0; a < kk; ++a) yK[a] = y[K[a]];
      const Eigen::VectorXd xK = LKK.transpose().triangularView<Eigen::Upper>().solve(yK);
      double worst = 0, scale = 0;
      for (size_t q = 0; q < c.kept.size(); ++q) {
        const int a = static_cast<int>(std::lower_bound(K.begin(), K.end(), S->iperm[c.kept[q]]) - K.begin());
        worst = std::max(worst, std::abs(out[q * kLanes + lane] - xK[a]));
        scale = std::max(scale, std::abs(xK[a]));
      }
      CHECK(scale > 0);
      CHECK(worst <= 1e-11 * scale);
    }
    // Same kept values as the unpruned planned solve (kernels/solve_sparse).
    std::vector<double> ref(out.size());
    solve_planned8(F, plan, rhs, ref, ws);
    double worst = 0, scale = 0;
    for (size_t q = 0; q < out.size(); ++q) {
      worst = std::max(worst, std::abs(out[q] - ref[q]));
      scale = std::max(scale, std::abs(ref[q]));
    }
    CHECK(worst <= 1e-12 * scale);
  }
  CHECK(pruned_cases >= 2);  // the compact patches skip part of the reach
}

TEST_CASE("pruned selective solve rejects exact plans and mismatched sizes") {
  const CscMatrix A = test::grid_laplacian(6, 6, 1.0);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  SolveWorkspace ws;
  const SolvePlan exact = plan_subset_solve(*F.symbolic, std::vector<int32_t>{0}, std::vector<int32_t>{3});
  std::vector<double> rhs(kLanes), out(kLanes);
  CHECK_THROWS_AS(solve_selective8(F, exact, rhs, out, ws), Error);
  const SolvePlan approx = plan_selective_solve(*F.symbolic, std::vector<int32_t>{0}, std::vector<int32_t>{3, 4});
  CHECK_THROWS_AS(solve_selective8(F, approx, rhs, out, ws), Error);  // out needs 2 x 8
}

TEST_CASE("pruned selective solve: x holds the touched columns only, same values as a full-length x") {
  const int nx = 48, ny = 40;
  const CscMatrix A = test::grid_laplacian(nx, ny, 0.05);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  const SymbolicFactor& S = *F.symbolic;
  const std::vector<int32_t> supp = grid_patch(nx, 5, 8, 5, 8), kept = grid_patch(nx, 2, 12, 2, 12);
  const SolvePlan plan = plan_selective_solve(S, supp, kept);
  int64_t touched = 0;
  for (int32_t s : plan.touched) touched += S.ncols(s);
  REQUIRE(touched < F.n());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> rhs(supp.size() * kLanes), out(kept.size() * kLanes), wide(out.size());
  for (auto& v : rhs) v = u(rng);
  SolveWorkspace compact, full;
  solve_selective8(F, plan, rhs, out, compact);
  CHECK(static_cast<int64_t>(compact.x.size()) == touched * kLanes);
  // A workspace already sized n x 8 (by a full-length solve) gives the same bits.
  full.x.assign(static_cast<size_t>(F.n()) * kLanes, 0.0);
  solve_selective8(F, plan, rhs, wide, full);
  CHECK(out == wide);
  CHECK(std::all_of(full.x.begin(), full.x.end(), [](double v) { return v == 0.0; }));
  CHECK(std::all_of(full.keep.begin(), full.keep.end(), [](uint8_t v) { return v == 0; }));
}

TEST_CASE("selective solve reads: a full plan reads the whole factor twice, a local plan less") {
  const int nx = 48, ny = 40;
  const CscMatrix A = test::grid_laplacian(nx, ny, 0.05);
  auto S = analyze(A, order_matrix(A));
  const int32_t n = S->n;
  // Stored entries = the analysis' own count of L's trapezoids.
  CHECK(factor_entries(*S) == S->nnz_L);
  std::vector<uint8_t> mark;
  std::vector<int32_t> every(n);
  for (int32_t i = 0; i < n; ++i) every[i] = i;
  // Everything kept, every row a source: forward and backward read every entry once.
  const SolvePlan all = plan_selective_solve(*S, every, every);
  CHECK(selective_solve_reads(*S, all, mark) == 2 * S->nnz_L);
  CHECK(std::all_of(mark.begin(), mark.end(), [](uint8_t v) { return v == 0; }));
  // A compact patch: at least its kept columns' stored entries (the backward reads
  // each kept column), far less than a full solve.
  const std::vector<int32_t> kept = grid_patch(nx, 17, 30, 13, 26), supp = grid_patch(nx, 22, 25, 18, 21);
  const SolvePlan local = plan_selective_solve(*S, supp, kept);
  int64_t kept_entries = 0;
  for (int32_t c : local.kept_cols) {
    const int32_t s = S->col_to_super[c];
    kept_entries += S->nrows(s) - (c - S->super_first_col[s]);
  }
  const int64_t reads = selective_solve_reads(*S, local, mark);
  CHECK(reads >= kept_entries);
  CHECK(reads < S->nnz_L / 2);
  CHECK(std::all_of(mark.begin(), mark.end(), [](uint8_t v) { return v == 0; }));
  CHECK_THROWS_AS(selective_solve_reads(*S, plan_subset_solve(*S, supp, kept), mark), Error);
}
