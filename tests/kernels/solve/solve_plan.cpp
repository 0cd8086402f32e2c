// Tests for the planners of kernels/solve_plan added for the heat method's
// localized queries: the vertex -> supernode table gives the same plan as the
// two lookups, with supernode sets listed against an independent brute-force
// ancestor closure (std::set over the etree); a plan derived from a covering
// plan (plan_subset_solve_within) solves exactly (Eigen sparse Cholesky as the
// oracle), also when its sets are not prefixes of the cover's outputs (fallback).
#include "locus/kernels/solve/solve_plan.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

using test::random_set;
using Llt = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower>;

// Supernodes on the etree paths from `ids` to the root, ascending (brute force).
std::vector<int32_t> closure(const SymbolicFactor& S, const std::vector<int32_t>& ids) {
  std::set<int32_t> out;
  for (int32_t v : ids)
    for (int32_t s = S.col_to_super[S.iperm[v]]; s >= 0; s = S.super_parent[s]) out.insert(s);
  return {out.begin(), out.end()};
}

// x = A^{-1} b at `at` by the Eigen oracle, b = rhs on supp.
std::vector<double> oracle_at(const Llt& llt, int32_t n, const std::vector<int32_t>& supp,
                              const std::vector<double>& rhs, const std::vector<int32_t>& at) {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < supp.size(); ++k) b[supp[k]] += rhs[k];
  const Eigen::VectorXd x = llt.solve(b);
  std::vector<double> r;
  for (int32_t v : at) r.push_back(x[v]);
  return r;
}

double rel_error(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0, scale = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    worst = std::max(worst, std::abs(a[k] - b[k]));
    scale = std::max(scale, std::abs(b[k]));
  }
  return worst / std::max(scale, 1e-300);
}

}  // namespace

TEST_CASE("planning with the vertex-supernode table gives the plain plan, sets equal the etree closure") {
  const CscMatrix A = test::grid_laplacian(80, 70, 0.01);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  const SymbolicFactor& S = *F.symbolic;
  const HostVector<int32_t> vs = vertex_supernodes(S);
  REQUIRE(vs.size() == static_cast<size_t>(S.n));
  std::mt19937_64 rng(5);
  SolvePlan p;
  PlanWorkspace ws;
  // Small sets (sorted), large ones (read off the bit set), then small again.
  for (int32_t count : {1, 19, 3000, 5600, 7}) {
    CAPTURE(count);
    const std::vector<int32_t> supp = random_set(S.n, std::min(count, 25), rng);
    const std::vector<int32_t> wanted = random_set(S.n, count, rng);
    plan_subset_solve(S, vs, supp, wanted, p, ws);
    const SolvePlan plain = plan_subset_solve(S, supp, wanted);
    CHECK(p.forward == plain.forward);
    CHECK(p.backward == plain.backward);
    CHECK(p.touched == plain.touched);
    CHECK(p.forward == closure(S, supp));
    std::vector<int32_t> back = closure(S, wanted);
    std::reverse(back.begin(), back.end());
    CHECK(p.backward == back);
    CHECK(std::all_of(ws.seen.begin(), ws.seen.end(), [](uint8_t m) { return m == 0; }));
  }
  const std::vector<int32_t> short_table(5, 0);
  CHECK_THROWS_AS(plan_subset_solve(S, short_table, std::vector<int32_t>{1}, std::vector<int32_t>{2}, p, ws), Error);
}

TEST_CASE("a plan derived from a covering plan solves exactly") {
  const CscMatrix grid = test::grid_laplacian(60, 50, 0.01);
  const CscMatrix rnd = test::random_spd(1500, 4, 3);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const CscMatrix* A : {&grid, &rnd}) {
    const NumericFactor F = factorize(analyze(*A, order_matrix(*A)), *A);
    const SymbolicFactor& S = *F.symbolic;
    const Llt llt(test::to_eigen(*A));
    REQUIRE(llt.info() == Eigen::Success);
    // The heat step: a few sources, wanted = a region (patch first, then its ring).
    std::vector<int32_t> region;
    for (int32_t i = S.n / 3; i < S.n / 3 + 500; ++i) region.push_back(i);
    const SolvePlan cover = plan_subset_solve(S, std::vector<int32_t>{S.n / 3 + 7}, region);
    SolvePlan p;
    PlanWorkspace ws;
    SolveWorkspace sws;
    // The Poisson step: support = the whole region, wanted = the patch (prefixes).
    const std::vector<int32_t> supp(region.begin(), region.end());
    const std::vector<int32_t> wanted(region.begin(), region.begin() + 400);
    plan_subset_solve_within(S, cover, supp, wanted, p, ws);
    CHECK(p.forward.size() == cover.backward.size());  // taken from the cover, not planned again
    CHECK(p.backward == cover.backward);
    std::vector<double> rhs(supp.size()), out(wanted.size());
    for (auto& v : rhs) v = u(rng);
    solve_planned(F, p, rhs, out, sws);
    CHECK(rel_error(out, oracle_at(llt, S.n, supp, rhs, wanted)) <= 1e-11);
    // Not prefixes of the cover's outputs: planned afresh, still exact.
    const std::vector<int32_t> other = random_set(S.n, 30, rng);
    plan_subset_solve_within(S, cover, other, wanted, p, ws);
    CHECK(p.forward == plan_subset_solve(S, other, wanted).forward);
    rhs.assign(other.size(), 0.0);
    for (auto& v : rhs) v = u(rng);
    solve_planned(F, p, rhs, out, sws);
    CHECK(rel_error(out, oracle_at(llt, S.n, other, rhs, wanted)) <= 1e-11);
    CHECK_THROWS_AS(plan_subset_solve_within(S, p, supp, wanted, p, ws), Error);
  }
}

// Oracle: the bytes summed over the brute-force etree closures (std::set), each
// block's size from its row and column counts (not from super_value_ptr).
TEST_CASE("plan_traffic counts the factor bytes of both passes, shared supernodes once") {
  const CscMatrix A = test::grid_laplacian(70, 60, 0.01);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  const SymbolicFactor& S = *F.symbolic;
  auto block = [&S](int32_t s) {
    return 8 * static_cast<int64_t>(S.nrows(s)) * S.ncols(s) + 4 * static_cast<int64_t>(S.nrows(s));
  };
  std::mt19937_64 rng(11);
  for (int32_t count : {1, 40, 2000}) {
    CAPTURE(count);
    const std::vector<int32_t> supp = random_set(S.n, std::min(count, 9), rng);
    const std::vector<int32_t> wanted = random_set(S.n, count, rng);
    const SolvePlan p = plan_subset_solve(S, supp, wanted);
    const std::vector<int32_t> fw = closure(S, supp), bw = closure(S, wanted);
    std::set<int32_t> both(fw.begin(), fw.end());
    both.insert(bw.begin(), bw.end());
    int64_t f = 0, b = 0, d = 0;
    for (int32_t s : fw) f += block(s);
    for (int32_t s : bw) b += block(s);
    for (int32_t s : both) d += block(s);
    const PlanTraffic t = plan_traffic(S, p);
    CHECK(t.forward_bytes == f);
    CHECK(t.backward_bytes == b);
    CHECK(t.distinct_bytes == d);
    CHECK(t.read_bytes() == f + b);
    CHECK(d < f + b);  // the root is on both paths
  }
  SolvePlan bad;
  bad.forward = {S.ns};
  CHECK_THROWS_AS(plan_traffic(S, bad), Error);
}
