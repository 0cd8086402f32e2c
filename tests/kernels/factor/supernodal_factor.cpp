// Tests for kernels/supernodal_factor: L against Eigen's SimplicialLLT with the
// same permutation (the Cholesky factor is unique), residuals, the SPD suite,
// not-positive-definite errors, refactorization and thread-count determinism.
#include "locus/kernels/factor/supernodal_factor.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <string_view>
#include <vector>

#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

double residual(const CscMatrix& A, const std::vector<double>& x, const std::vector<double>& b) {
  std::vector<double> Ax(b.size());
  symmetric_multiply(A, x.data(), Ax.data());
  double num = 0, den = 0;
  for (size_t i = 0; i < b.size(); ++i) { num += (Ax[i] - b[i]) * (Ax[i] - b[i]); den += b[i] * b[i]; }
  return std::sqrt(num / den);
}

std::vector<double> random_vector(int32_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> b(n);
  for (auto& v : b) v = u(rng);
  return b;
}

// L(i, j) in factor numbering, from the supernodal storage (0 where not stored).
double entry(const NumericFactor& F, int32_t i, int32_t j) {
  const SymbolicFactor& S = *F.symbolic;
  const int32_t s = S.col_to_super[j];
  const int32_t* rows = S.super_rows.data() + S.super_row_ptr[s];
  const int32_t* hit = std::lower_bound(rows, rows + S.nrows(s), i);
  if (hit == rows + S.nrows(s) || *hit != i) return 0.0;
  return F.block(s)[static_cast<int64_t>(j - S.super_first_col[s]) * S.nrows(s) + (hit - rows)];
}

void check_against_eigen(const CscMatrix& A, int threads) {
  const int32_t n = A.ncols;
  auto S = analyze(A, order_matrix(A));
  RunContext ctx;
  ctx.threads = threads;
  NumericFactor F = factorize(S, A, ctx);
  // Eigen factor of P A P^T with natural ordering: same unique L.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(n);
  for (int32_t k = 0; k < n; ++k) P.indices()[S->perm[k]] = k;
  Eigen::SparseMatrix<double> E = test::to_eigen(A);
  Eigen::SparseMatrix<double> PE = (P * E * P.transpose()).eval();
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(PE);
  REQUIRE(llt.info() == Eigen::Success);
  const Eigen::SparseMatrix<double> L = llt.matrixL();
  CHECK(L.nonZeros() == S->nnz_exact);
  double maxdiff = 0, maxval = 0;
  for (int k = 0; k < L.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, k); it; ++it) {
      maxdiff = std::max(maxdiff, std::abs(it.value() - entry(F, static_cast<int32_t>(it.row()), static_cast<int32_t>(it.col()))));
      maxval = std::max(maxval, std::abs(it.value()));
    }
  CHECK(maxdiff <= 1e-12 * maxval);
  // Solves agree with Eigen's and have small residuals.
  const std::vector<double> b = random_vector(n, 42);
  std::vector<double> x = b;
  solve(F, x);
  CHECK(residual(A, x, b) <= 1e-10);
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> ref(E);
  Eigen::VectorXd xe = ref.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), n));
  double dx = 0, nx = 0;
  for (int32_t i = 0; i < n; ++i) { dx = std::max(dx, std::abs(x[i] - xe[i])); nx = std::max(nx, std::abs(xe[i])); }
  CHECK(dx <= 1e-10 * nx);
}

}  // namespace

TEST_CASE("numeric factor equals Eigen's SimplicialLLT under the same permutation") {
  for (int threads : {1, 2}) {
    CAPTURE(threads);
    check_against_eigen(test::grid_laplacian(40, 37, 0.01), threads);
    check_against_eigen(test::grid_laplacian(90, 80, 1e-3), threads);
    check_against_eigen(test::grid_laplacian(330, 310, 1e-3), threads);  // wide root supernodes: blocked parallel path
    for (uint64_t seed = 1; seed <= 4; ++seed) check_against_eigen(test::random_spd(500 + 300 * seed, 3, seed), threads);
  }
}

TEST_CASE("every matrix of the third-party SPD suite factors and solves, or is reported not positive definite") {
  for (const char* f : {"bcsstk01.tri", "bcsstk02.tri", "pts5ldd03.mtx", "two.tri", "bcsstk01.rsa", "bcsstk02.rsa"}) {
    CAPTURE(f);
    const std::string path = std::string(LOCUS_TEST_DATA_DIR) + "/" + f;
    const CscMatrix A = std::string(f).ends_with(".rsa") ? test::read_rsa_file(path) : test::read_triplet_file(path);
    auto S = analyze(A, order_matrix(A));
    // Eigen decides independently whether the matrix is numerically SPD.
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> ref(test::to_eigen(A));
    if (ref.info() != Eigen::Success) {
      CHECK_THROWS_AS(factorize(S, A), Error);
      continue;
    }
    NumericFactor F = factorize(S, A);
    const std::vector<double> b = random_vector(A.ncols, 7);
    std::vector<double> x = b;
    solve(F, x);
    CHECK(residual(A, x, b) <= 1e-10);
  }
  // bcsstk01 in both formats is the same matrix.
  const CscMatrix a = test::read_triplet_file(std::string(LOCUS_TEST_DATA_DIR) + "/bcsstk01.tri");
  const CscMatrix b = test::read_rsa_file(std::string(LOCUS_TEST_DATA_DIR) + "/bcsstk01.rsa");
  CHECK(a.rowind == b.rowind);
  CHECK(a.values.size() == b.values.size());
}

TEST_CASE("an indefinite matrix raises the not-positive-definite error naming the vertex") {
  for (int32_t bad : {0, 137, 399}) {
    CAPTURE(bad);
    CscMatrix A = test::random_spd(400, 4, 5);
    for (int64_t p = A.colptr[bad]; p < A.colptr[bad + 1]; ++p)
      if (A.rowind[p] == bad) A.values[p] = -1.0;
    auto S = analyze(A, order_matrix(A));
    for (int threads : {1, 2}) {
      RunContext ctx;
      ctx.threads = threads;
      try {
        factorize(S, A, ctx);
        FAIL("no error raised");
      } catch (const Error& e) {
        CHECK(e.code() == ErrorCode::Numerical);
        const std::string msg = e.what();
        CHECK(msg.find("not positive definite at vertex " + std::to_string(bad) + " ") != std::string::npos);
        CHECK(msg.find("column " + std::to_string(S->iperm[bad])) != std::string::npos);
        CHECK(e.where().vertex == bad);
        CHECK(e.where().column == S->iperm[bad]);
      }
    }
  }
}

TEST_CASE("refactorization reuses the symbolic factor; the factor is identical for 1 and 2 threads") {
  CscMatrix A = test::grid_laplacian(330, 300, 0.05);
  auto S = analyze(A, order_matrix(A));
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  NumericFactor F1 = factorize(S, A, one);
  NumericFactor F2 = factorize(S, A, two);
  CHECK(std::equal(F1.values.begin(), F1.values.end(), F2.values.begin()));
  CscMatrix B = A;
  for (int32_t j = 0; j < B.ncols; ++j) B.values[B.colptr[j]] += 3.0;  // diagonal entries come first
  refactorize(F2, B, two);
  NumericFactor Fb = factorize(S, B, one);
  CHECK(F2.symbolic == S);
  CHECK(std::equal(F2.values.begin(), F2.values.end(), Fb.values.begin()));
  const std::vector<double> b = random_vector(B.ncols, 3);
  std::vector<double> x = b;
  solve(F2, x);
  CHECK(residual(B, x, b) <= 1e-12);
  // A different pattern is refused.
  CscMatrix C = test::grid_laplacian(330, 300, 0.05);
  C.rowind.back() = C.rowind.back();  // same pattern: accepted
  CHECK_NOTHROW(refactorize(F2, C, one));
  CscMatrix D = test::grid_laplacian(300, 330, 0.05);
  CHECK_THROWS_AS(refactorize(F2, D, one), Error);
}

TEST_CASE("factorize_supernodes recomputes exactly the masked supernodes") {
  const CscMatrix A = test::grid_laplacian(50, 40, 0.1);
  auto S = analyze(A, order_matrix(A));
  const NumericFactor ref = factorize(S, A);
  NumericFactor F = ref;
  std::vector<uint8_t> mask(S->ns, 0);
  // Corrupt every third supernode and its ancestors' values, then recompute them.
  for (int32_t s = 0; s < S->ns; s += 3) {
    for (int32_t q = s; q >= 0; q = S->super_parent[q]) mask[q] = 1;
  }
  for (int32_t s = 0; s < S->ns; ++s)
    if (mask[s])
      for (int64_t p = S->super_value_ptr[s]; p < S->super_value_ptr[s + 1]; ++p) F.values[p] = 1e300;
  for (int threads : {1, 2}) {
    RunContext ctx;
    ctx.threads = threads;
    factorize_supernodes(F, A, mask, ctx);
    bool same = true;
    for (int32_t s = 0; s < S->ns; ++s)
      for (int32_t j = 0; j < S->ncols(s); ++j)  // compare the lower trapezoid only
        for (int32_t i = j; i < S->nrows(s); ++i) {
          const int64_t p = S->super_value_ptr[s] + static_cast<int64_t>(j) * S->nrows(s) + i;
          same = same && F.values[p] == ref.values[p];
        }
    CHECK(same);
  }
  std::vector<uint8_t> short_mask(3, 1);
  CHECK_THROWS_AS(factorize_supernodes(F, A, short_mask), Error);
}

TEST_CASE("non-finite matrix entries are refused before factoring") {
  CscMatrix A = test::grid_laplacian(10, 10, 0.1);
  auto S = analyze(A, order_matrix(A));
  for (double bad : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    CscMatrix B = A;
    B.values[B.colptr[37] + 1] = bad;
    try {
      factorize(S, B);
      FAIL("accepted a non-finite entry");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::Numerical);
      CHECK(std::string(e.what()).find("not finite") != std::string::npos);
    }
  }
}

TEST_CASE("the numeric factorization reports monotone progress and stops at a cancel raised from it") {
  // A C host cancels through its progress callback, so the
  // factorization must report while it works, not only at its ends.
  const CscMatrix A = test::grid_laplacian(330, 300, 0.05);
  auto S = analyze(A, order_matrix(A));
  std::mutex mu;
  std::vector<double> seen;
  bool names_ok = true;
  std::atomic<bool> cancel{false};
  double cancel_at = 2;  // raise the flag at the first report above this fraction (2: never)
  RunContext ctx;
  ctx.threads = 2;
  ctx.cancel = &cancel;
  ctx.progress = [&](double f, std::string_view phase) {
    std::lock_guard<std::mutex> lock(mu);
    names_ok = names_ok && phase == "numeric factorization";
    seen.push_back(f);
    if (f > cancel_at) cancel.store(true);
  };
  const NumericFactor F = factorize(S, A, ctx);
  REQUIRE(seen.size() >= 2);
  CHECK(names_ok);
  CHECK(seen.front() == 0.0);
  CHECK(seen.back() == 1.0);
  CHECK(std::is_sorted(seen.begin(), seen.end()));

  // Cancelled at its first report: no supernode is computed.
  seen.clear();
  cancel_at = -0.5;
  CHECK_THROWS_AS(factorize(S, A, ctx), Error);
  CHECK(seen.size() == 1);
  // Cancelled at a report from inside (when the factorization lasts long enough to give one).
  seen.clear();
  cancel.store(false);
  cancel_at = 0.0;
  bool thrown = false;
  try {
    factorize(S, A, ctx);
  } catch (const Error& e) {
    thrown = e.code() == ErrorCode::Cancelled;
  }
  const bool inside = std::any_of(seen.begin(), seen.end(), [](double f) { return f > 0 && f < 1; });
  CHECK(thrown == inside);
  if (inside) CHECK(seen.back() < 1.0);
}
