// Tests for kernels/selected_inversion: every entry on the pattern of L and the
// whole diagonal against a dense Eigen inverse; identical for 1 and 2 threads.
#include "locus/kernels/solve/selected_inversion.hpp"

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include <cmath>

#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

void check_against_dense(const CscMatrix& A, int threads) {
  auto S = analyze(A, order_matrix(A));
  const NumericFactor F = factorize(S, A);
  RunContext ctx;
  ctx.threads = threads;
  const SelectedInverse Z = selected_inversion(F, ctx);
  const Eigen::MatrixXd Ainv = Eigen::MatrixXd(test::to_eigen(A)).inverse();
  const double scale = Ainv.cwiseAbs().maxCoeff();
  const std::vector<double> d = inverse_diagonal(Z);
  double worst = 0;
  for (int32_t i = 0; i < A.ncols; ++i) worst = std::max(worst, std::abs(d[i] - Ainv(i, i)));
  CHECK(worst <= 1e-11 * scale);
  worst = 0;
  for (int32_t s = 0; s < S->ns; ++s)
    for (int32_t j = S->super_first_col[s]; j < S->super_first_col[s + 1]; ++j)
      for (int64_t p = S->super_row_ptr[s] + (j - S->super_first_col[s]); p < S->super_row_ptr[s + 1]; ++p) {
        const int32_t a = S->perm[S->super_rows[p]], b = S->perm[j];
        worst = std::max(worst, std::abs(inverse_entry(Z, a, b) - Ainv(a, b)));
      }
  CHECK(worst <= 1e-11 * scale);
}

}  // namespace

TEST_CASE("selected inversion equals the dense inverse on the pattern of L") {
  for (int threads : {1, 2}) {
    CAPTURE(threads);
    check_against_dense(test::grid_laplacian(25, 22, 0.05), threads);
    check_against_dense(test::random_spd(400, 5, 3), threads);
    check_against_dense(test::read_triplet_file(std::string(LOCUS_TEST_DATA_DIR) + "/bcsstk02.tri"), threads);
  }
}

TEST_CASE("selected inversion is identical for 1 and 2 threads") {
  const CscMatrix A = test::grid_laplacian(150, 140, 0.01);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  const SelectedInverse Z1 = selected_inversion(F, one), Z2 = selected_inversion(F, two);
  CHECK(inverse_diagonal(Z1) == inverse_diagonal(Z2));
  CHECK_THROWS_AS(inverse_entry(Z1, 0, A.ncols - 1), Error);  // far corners of a grid: not on the pattern
}
