// Tests for kernels/solve_full: 1-lane and 8-lane solves against each other and
// against residuals, on matrices with small and wide (BLAS-path) supernodes.
#include "locus/kernels/solve/solve_full.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

TEST_CASE("8-lane solves equal eight 1-lane solves and solve the system") {
  for (int nx : {7, 60, 150}) {
    CAPTURE(nx);
    const CscMatrix A = test::grid_laplacian(nx, nx, 0.02);
    const int32_t n = A.ncols;
    NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
    std::mt19937_64 rng(nx);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> b8(static_cast<size_t>(n) * kLanes);
    for (auto& v : b8) v = u(rng);
    std::vector<double> x8 = b8;
    solve8(F, x8);
    double worst_diff = 0, worst_res = 0;
    for (int lane = 0; lane < kLanes; ++lane) {
      std::vector<double> b(n), x(n), Ax(n);
      for (int32_t i = 0; i < n; ++i) b[i] = b8[static_cast<size_t>(i) * kLanes + lane];
      x = b;
      solve(F, x);
      symmetric_multiply(A, x.data(), Ax.data());
      double r = 0, nb = 0;
      for (int32_t i = 0; i < n; ++i) {
        worst_diff = std::max(worst_diff, std::abs(x[i] - x8[static_cast<size_t>(i) * kLanes + lane]) / (1 + std::abs(x[i])));
        r += (Ax[i] - b[i]) * (Ax[i] - b[i]);
        nb += b[i] * b[i];
      }
      worst_res = std::max(worst_res, std::sqrt(r / nb));
    }
    CHECK(worst_diff <= 1e-12);
    CHECK(worst_res <= 1e-10);
  }
}

TEST_CASE("solves check their argument sizes") {
  const CscMatrix A = test::grid_laplacian(5, 5, 1.0);
  NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  std::vector<double> wrong(24);
  CHECK_THROWS_AS(solve(F, wrong), Error);
  std::vector<double> wrong8(25 * 7);
  CHECK_THROWS_AS(solve8(F, wrong8), Error);
  NumericFactor empty;
  std::vector<double> none;
  CHECK_THROWS_AS(solve(empty, none), Error);
}
