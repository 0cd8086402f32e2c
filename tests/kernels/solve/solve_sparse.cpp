// Tests for kernels/solve_plan + kernels/solve_sparse: exact subset solves
// equal the full solve at the wanted entries (single entries, far-apart pairs,
// patches, disjoint support/wanted, everything), 8 lanes equal 1 lane, and the
// approximate selective solve equals an independent dense evaluation of
// thesis Algorithm 2 (x_K = (L^T)_KK^{-1} (L^{-1} b)_K, zero elsewhere).
#include "locus/kernels/solve/solve_sparse.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

using test::random_set;

// Full solve of b (support/values), returned at `at`.
std::vector<double> full_at(const NumericFactor& F, const std::vector<int32_t>& supp, const std::vector<double>& vals,
                            const std::vector<int32_t>& at) {
  std::vector<double> b(F.n(), 0.0);
  for (size_t k = 0; k < supp.size(); ++k) b[supp[k]] += vals[k];
  solve(F, b);
  std::vector<double> r;
  for (int32_t v : at) r.push_back(b[v]);
  return r;
}

// Plans into a plan object reused across calls (big plans followed by small
// ones), checks it equals a freshly built plan, then solves with it.
void check_exact(const NumericFactor& F, const std::vector<int32_t>& supp, const std::vector<int32_t>& wanted,
                 SolveWorkspace& ws, std::mt19937_64& rng) {
  static thread_local SolvePlan plan;
  static thread_local PlanWorkspace pws;
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> vals(supp.size());
  for (auto& v : vals) v = u(rng);
  plan_subset_solve(*F.symbolic, supp, wanted, plan, pws);
  const SolvePlan fresh = plan_subset_solve(*F.symbolic, supp, wanted);
  CHECK(plan.forward == fresh.forward);
  CHECK(plan.backward == fresh.backward);
  CHECK(plan.touched == fresh.touched);
  CHECK(plan.forward_columns == fresh.forward_columns);
  CHECK(plan.backward_columns == fresh.backward_columns);
  std::vector<double> out(wanted.size());
  solve_planned(F, plan, vals, out, ws);
  const std::vector<double> ref = full_at(F, supp, vals, wanted);
  double worst = 0, scale = 0;
  for (size_t k = 0; k < out.size(); ++k) {
    worst = std::max(worst, std::abs(out[k] - ref[k]));
    scale = std::max(scale, std::abs(ref[k]));
  }
  CHECK(worst <= 1e-12 * scale);
  CHECK(std::all_of(ws.x.begin(), ws.x.end(), [](double v) { return v == 0.0; }));
}

}  // namespace

TEST_CASE("exact subset solves equal the full solve at the wanted entries") {
  const CscMatrix grid = test::grid_laplacian(70, 60, 0.01);
  const CscMatrix rnd = test::random_spd(3000, 4, 11);
  std::mt19937_64 rng(5);
  for (const CscMatrix* A : {&grid, &rnd}) {
    const NumericFactor F = factorize(analyze(*A, order_matrix(*A)), *A);
    const int32_t n = F.n();
    SolveWorkspace ws;
    check_exact(F, {0}, {0}, ws, rng);                   // single entry
    check_exact(F, {n - 1}, {0}, ws, rng);               // far-apart pair
    check_exact(F, {0, n - 1}, {n / 2, n / 3}, ws, rng);
    std::vector<int32_t> patch;                           // a contiguous block (a patch on the grid)
    for (int32_t i = n / 2; i < n / 2 + 400; ++i) patch.push_back(i);
    check_exact(F, patch, patch, ws, rng);
    check_exact(F, {n / 4}, patch, ws, rng);              // disjoint support and wanted
    std::vector<int32_t> all(n);
    for (int32_t i = 0; i < n; ++i) all[i] = i;
    check_exact(F, all, all, ws, rng);                    // everything
    for (int trial = 0; trial < 20; ++trial)
      check_exact(F, random_set(n, 1 + trial * 7, rng), random_set(n, 1 + trial * 13, rng), ws, rng);
  }
}

TEST_CASE("8-lane planned solves equal 1-lane planned solves") {
  const CscMatrix A = test::grid_laplacian(120, 90, 0.01);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  SolveWorkspace ws;
  for (bool approximate : {false, true}) {
    const std::vector<int32_t> supp = random_set(F.n(), 30, rng), outs = random_set(F.n(), 500, rng);
    const SolvePlan plan = approximate ? plan_selective_solve(*F.symbolic, supp, outs) : plan_subset_solve(*F.symbolic, supp, outs);
    std::vector<double> rhs8(supp.size() * kLanes), out8(outs.size() * kLanes);
    for (auto& v : rhs8) v = u(rng);
    solve_planned8(F, plan, rhs8, out8, ws);
    for (int lane = 0; lane < kLanes; ++lane) {
      std::vector<double> rhs(supp.size()), out(outs.size());
      for (size_t k = 0; k < supp.size(); ++k) rhs[k] = rhs8[k * kLanes + lane];
      solve_planned(F, plan, rhs, out, ws);
      double worst = 0;
      for (size_t k = 0; k < outs.size(); ++k) worst = std::max(worst, std::abs(out[k] - out8[k * kLanes + lane]) / (1 + std::abs(out[k])));
      CHECK(worst <= 1e-12);
    }
  }
}

TEST_CASE("approximate selective solve equals a dense evaluation of Algorithm 2") {
  const CscMatrix A = test::grid_laplacian(30, 25, 0.05);
  auto S = analyze(A, order_matrix(A));
  const NumericFactor F = factorize(S, A);
  const int32_t n = F.n();
  // Independent L (factor numbering) from Eigen.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(n);
  for (int32_t k = 0; k < n; ++k) P.indices()[S->perm[k]] = k;
  Eigen::SparseMatrix<double> E = test::to_eigen(A);
  Eigen::SparseMatrix<double> PE = (P * E * P.transpose()).eval();
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(PE);
  const Eigen::MatrixXd L = Eigen::MatrixXd(Eigen::SparseMatrix<double>(llt.matrixL()));
  std::mt19937_64 rng(3);
  SolveWorkspace ws;
  for (int32_t kept_count : {1, 40, 300, n}) {
    CAPTURE(kept_count);
    const std::vector<int32_t> supp = random_set(n, 3, rng);
    std::vector<int32_t> kept = random_set(n, kept_count, rng);
    kept.push_back(supp[0]);
    std::vector<double> vals = {1.0, -0.5, 2.0};
    const SolvePlan plan = plan_selective_solve(*S, supp, kept);
    std::vector<double> out(kept.size());
    solve_planned(F, plan, vals, out, ws);
    // Oracle: y = L^{-1} P b; x_K = (L^T)_KK^{-1} y_K.
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (size_t k = 0; k < supp.size(); ++k) b[S->iperm[supp[k]]] += vals[k];
    const Eigen::VectorXd y = L.triangularView<Eigen::Lower>().solve(b);
    std::vector<int32_t> K;
    for (int32_t v : kept) K.push_back(S->iperm[v]);
    std::sort(K.begin(), K.end());
    K.erase(std::unique(K.begin(), K.end()), K.end());
    const int kk = static_cast<int>(K.size());
    Eigen::MatrixXd LKK(kk, kk);
    Eigen::VectorXd yK(kk);
    for (int a = 0; a < kk; ++a) {
      yK[a] = y[K[a]];
      for (int c = 0; c < kk; ++c) LKK(a, c) = L(K[a], K[c]);
    }
    const Eigen::VectorXd xK = LKK.transpose().triangularView<Eigen::Upper>().solve(yK);
    double worst = 0, scale = 0;
    for (size_t q = 0; q < kept.size(); ++q) {
      const int a = static_cast<int>(std::lower_bound(K.begin(), K.end(), S->iperm[kept[q]]) - K.begin());
      worst = std::max(worst, std::abs(out[q] - xK[a]));
      scale = std::max(scale, std::abs(xK[a]));
    }
    CHECK(worst <= 1e-11 * scale);
    if (kept_count == n) {  // keeping everything is the exact solve
      const std::vector<double> ref = full_at(F, supp, vals, kept);
      for (size_t q = 0; q < kept.size(); ++q) CHECK(std::abs(out[q] - ref[q]) <= 1e-12 * scale);
    }
  }
}

TEST_CASE("plans reject out-of-range vertices and mismatched sizes") {
  const CscMatrix A = test::grid_laplacian(6, 6, 1.0);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  CHECK_THROWS_AS(plan_subset_solve(*F.symbolic, std::vector<int32_t>{36}, std::vector<int32_t>{0}), Error);
  CHECK_THROWS_AS(plan_selective_solve(*F.symbolic, std::vector<int32_t>{0}, std::vector<int32_t>{-1}), Error);
  const SolvePlan plan = plan_subset_solve(*F.symbolic, std::vector<int32_t>{0, 1}, std::vector<int32_t>{3});
  SolveWorkspace ws;
  std::vector<double> rhs(1), out(1);
  CHECK_THROWS_AS(solve_planned(F, plan, rhs, out, ws), Error);
}
