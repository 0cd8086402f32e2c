// Tests for kernels/solve_wide: every lane of the many-lane subset solve
// equals an independent Eigen sparse Cholesky solve at the wanted entries, for
// 8 to 32 lanes, small and wide supernodes, disjoint support and wanted sets,
// repeated support entries; the workspace is reused across plans of different
// sizes; results left in the workspace (no output span) are the same; the
// one-lane solve equals each lane bit for bit; bad arguments are refused by name.
#include "locus/kernels/solve/solve_wide.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

using test::random_set;

using Llt = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower>;

void check_wide(const NumericFactor& F, const Llt& oracle, const std::vector<int32_t>& supp,
                const std::vector<int32_t>& wanted, int lanes, WideSolveWorkspace& ws, std::mt19937_64& rng) {
  CAPTURE(lanes);
  CAPTURE(supp.size());
  CAPTURE(wanted.size());
  std::uniform_real_distribution<double> u(-1, 1);
  const SolvePlan plan = plan_subset_solve(*F.symbolic, supp, wanted);
  std::vector<double> rhs(supp.size() * lanes), out(wanted.size() * lanes, -7.0);
  for (auto& v : rhs) v = u(rng);
  solve_planned_wide(F, plan, lanes, rhs, out, ws);
  double worst = 0;
  for (int l = 0; l < lanes; ++l) {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(F.n());
    for (size_t k = 0; k < supp.size(); ++k) b[supp[k]] += rhs[k * lanes + l];
    const Eigen::VectorXd x = oracle.solve(b);
    const double scale = x.cwiseAbs().maxCoeff();
    for (size_t k = 0; k < wanted.size(); ++k)
      worst = std::max(worst, std::abs(out[k * lanes + l] - x[wanted[k]]) / scale);
  }
  CHECK(worst <= 1e-11);
  // Without an output span the results stay in the workspace, output k at row
  // out_rows[k]: the same numbers the copy holds.
  const std::vector<double> copied = out;
  solve_planned_wide(F, plan, lanes, rhs, {}, ws);
  REQUIRE(ws.out_rows.size() == wanted.size());
  bool same = true;
  for (size_t k = 0; k < wanted.size(); ++k)
    for (int l = 0; l < lanes; ++l)
      same &= ws.x[static_cast<size_t>(ws.out_rows[k]) * lanes + l] == copied[k * lanes + l];
  CHECK(same);
  // The one-lane solve gives each lane's numbers bit for bit.
  WideSolveWorkspace one;
  for (int l : {0, lanes - 1}) {
    std::vector<double> r1(supp.size());
    for (size_t k = 0; k < supp.size(); ++k) r1[k] = rhs[k * lanes + l];
    solve_planned_lane(F, plan, r1, one);
    REQUIRE(one.out_rows.size() == wanted.size());
    bool equal = true;
    for (size_t k = 0; k < wanted.size(); ++k) equal &= one.x[static_cast<size_t>(one.out_rows[k])] == copied[k * lanes + l];
    CHECK(equal);
  }
}

}  // namespace

TEST_CASE("wide subset solves equal an independent sparse Cholesky solve in every lane") {
  const CscMatrix grid = test::grid_laplacian(70, 60, 0.01);  // separators of ~60 columns: wide supernodes
  const CscMatrix rnd = test::random_spd(2000, 4, 11);
  std::mt19937_64 rng(17);
  for (const CscMatrix* A : {&grid, &rnd}) {
    const NumericFactor F = factorize(analyze(*A, order_matrix(*A)), *A);
    const Llt oracle(test::to_eigen(*A));
    REQUIRE(oracle.info() == Eigen::Success);
    const int32_t n = F.n();
    WideSolveWorkspace ws;
    std::vector<int32_t> patch;  // a contiguous block: a patch of the grid
    for (int32_t i = n / 2; i < n / 2 + 400; ++i) patch.push_back(i);
    std::vector<int32_t> all(n);
    for (int32_t i = 0; i < n; ++i) all[i] = i;
    for (int lanes : {8, 16, 24, 32}) {
      check_wide(F, oracle, {0}, {0}, lanes, ws, rng);
      check_wide(F, oracle, {n - 1}, {0}, lanes, ws, rng);  // far apart
      check_wide(F, oracle, random_set(n, 19, rng), patch, lanes, ws, rng);
      check_wide(F, oracle, {n / 4, n / 4, 3}, patch, lanes, ws, rng);  // repeated support entries sum
      check_wide(F, oracle, all, all, lanes, ws, rng);                  // everything
      check_wide(F, oracle, random_set(n, 7, rng), random_set(n, 50, rng), lanes, ws, rng);  // small after big
    }
  }
}

TEST_CASE("wide subset solve: bad arguments are refused") {
  const CscMatrix A = test::grid_laplacian(10, 10, 0.1);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  const SolvePlan plan = plan_subset_solve(*F.symbolic, std::vector<int32_t>{1, 2}, std::vector<int32_t>{5});
  WideSolveWorkspace ws;
  std::vector<double> rhs(2 * 16), out(16);
  auto code = [&](auto fn) {
    try {
      fn();
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::Internal;
  };
  CHECK(code([&] { solve_planned_wide(F, plan, 12, rhs, out, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { solve_planned_wide(F, plan, 40, rhs, out, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { solve_planned_wide(F, plan, 8, rhs, out, ws); }) == ErrorCode::BadUsage);  // sizes for 16 lanes
  const SolvePlan approx = plan_selective_solve(*F.symbolic, std::vector<int32_t>{1, 2}, std::vector<int32_t>{5});
  CHECK(code([&] { solve_planned_wide(F, approx, 16, rhs, out, ws); }) == ErrorCode::BadUsage);
  solve_planned_wide(F, plan, 16, rhs, out, ws);  // the right sizes pass
  std::vector<double> one(2), three(3);
  CHECK(code([&] { solve_planned_lane(F, plan, three, ws); }) == ErrorCode::BadUsage);
  CHECK(code([&] { solve_planned_lane(F, approx, one, ws); }) == ErrorCode::BadUsage);
  solve_planned_lane(F, plan, one, ws);
}
