// Tests for pipelines/heat_exchange (thesis §4.6, pairwise heat exchange).
// Oracle: an Eigen SimplicialLDLT solve of heat_operator(m, t) with the unit
// sources, read at the targets (independent of locus's factor and plans).
// Also checked: symmetry of the exchange (A is symmetric), and that separate
// forward/backward subtrees never visit more columns than the union subtree.
#include "locus/pipelines/heat/heat_exchange.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <cmath>
#include <numeric>
#include <random>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

std::vector<int32_t> random_set(int32_t n, int count, std::mt19937_64& rng) {
  std::uniform_int_distribution<int32_t> pick(0, n - 1);
  std::vector<int32_t> s(static_cast<size_t>(count));
  for (int32_t& v : s) v = pick(rng);
  return s;
}

void check_mesh(const Mesh& m, double t_h2) {
  const double h = mean_edge_length(m);
  const double t = t_h2 * h * h;
  const HeatFactors H = factor_heat_operators(m, std::vector<double>{t});
  const NumericFactor& F = H.factors[0];
  const Eigen::SparseMatrix<double> A = test::to_eigen(heat_operator(m, t));
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  REQUIRE(ldlt.info() == Eigen::Success);
  const int32_t n = m.num_vertices();
  std::mt19937_64 rng(7);
  HeatWorkspace ws;
  for (int trial = 0; trial < 30; ++trial) {
    const int ns = trial < 10 ? 1 : 1 + trial % 6, nt = trial < 10 ? 1 : 1 + (trial * 7) % 9;
    const std::vector<int32_t> S = random_set(n, ns, rng), T = random_set(n, nt, rng);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (int32_t s : S) b[s] += 1.0;
    const Eigen::VectorXd x = ldlt.solve(b);
    double scale = 0;
    for (int32_t v : T) scale = std::max(scale, std::abs(x[v]));
    HeatExchangeStats st[3];
    for (HeatExchangeMethod method : {HeatExchangeMethod::Subset, HeatExchangeMethod::Union, HeatExchangeMethod::Full}) {
      CAPTURE(heat_exchange_method_name(method));
      std::vector<double> out(T.size());
      heat_exchange(F, S, T, method, out, ws, &st[static_cast<int>(method)]);
      double worst = 0;
      for (size_t k = 0; k < T.size(); ++k) worst = std::max(worst, std::abs(out[k] - x[T[k]]));
      CHECK(worst <= 1e-10 * scale);
    }
    CHECK(st[0].forward_columns <= st[1].forward_columns);
    CHECK(st[0].backward_columns <= st[1].backward_columns);
    // Symmetry: total heat S -> T equals total heat T -> S.
    std::vector<double> st_out(T.size()), ts_out(S.size());
    heat_exchange(F, S, T, HeatExchangeMethod::Subset, st_out, ws);
    heat_exchange(F, T, S, HeatExchangeMethod::Subset, ts_out, ws);
    const double a = std::accumulate(st_out.begin(), st_out.end(), 0.0);
    const double c = std::accumulate(ts_out.begin(), ts_out.end(), 0.0);
    CHECK(std::abs(a - c) <= 1e-10 * std::max(std::abs(a), std::abs(c)));
  }
  // The workspace is clean after all those queries.
  CHECK(std::all_of(ws.sparse.x.begin(), ws.sparse.x.end(), [](double v) { return v == 0.0; }));
}

}  // namespace

TEST_CASE("heat exchange: all methods equal an Eigen solve; symmetric") {
  SUBCASE("icosphere, t = 1 h^2") { check_mesh(make_icosphere(4), 1.0); }
  SUBCASE("torus, t = 500 h^2") { check_mesh(make_torus(60, 24), 500.0); }
}

TEST_CASE("heat exchange: bad arguments") {
  const Mesh m = make_icosphere(1);
  const HeatFactors H = factor_heat_operators(m, std::vector<double>{0.01});
  HeatWorkspace ws;
  std::vector<double> out(1);
  const std::vector<int32_t> ok{0}, none{}, bad{-1};
  CHECK_THROWS_AS(heat_exchange(H.factors[0], none, ok, HeatExchangeMethod::Subset, out, ws), Error);
  CHECK_THROWS_AS(heat_exchange(H.factors[0], ok, bad, HeatExchangeMethod::Subset, out, ws), Error);
  std::vector<double> two(2);
  CHECK_THROWS_AS(heat_exchange(H.factors[0], ok, ok, HeatExchangeMethod::Full, two, ws), Error);
  CHECK_THROWS_AS(parse_heat_exchange_method("dot"), Error);
}
