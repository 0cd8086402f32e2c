// The minimum-degree orders of small graphs and of the nested dissection's
// leaves (minimum_degree.hpp): CAMD called on the graph directly
// gives the order of SuiteSparse's own entry point camd_order (the oracle:
// it checks and forms A + A^T itself), keeps each constraint set in its
// turn, and handles graphs without edges.
#include "locus/kernels/order/minimum_degree.hpp"

#include <camd.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

// A random graph on n vertices (about `per_row` random neighbors each, and a
// path through all so it is connected), lists ascending.
AdjacencyGraph random_graph(int32_t n, int per_row, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::set<int32_t>> rows(static_cast<size_t>(n));
  const auto join = [&](int32_t a, int32_t b) {
    if (a == b) return;
    rows[a].insert(b);
    rows[b].insert(a);
  };
  for (int32_t v = 0; v + 1 < n; ++v) join(v, v + 1);
  for (int32_t v = 0; v < n; ++v)
    for (int k = 0; k < per_row; ++k) join(v, static_cast<int32_t>(rng() % n));
  AdjacencyGraph g;
  for (const auto& r : rows) {
    g.adj.insert(g.adj.end(), r.begin(), r.end());
    g.xadj.push_back(static_cast<int32_t>(g.adj.size()));
  }
  return g;
}

HostVector<int32_t> camd_order_of(const AdjacencyGraph& g, const HostVector<int32_t>& constraint) {
  HostVector<int32_t> perm(static_cast<size_t>(g.n()));
  double control[CAMD_CONTROL], info[CAMD_INFO];
  camd_defaults(control);
  REQUIRE(camd_order(g.n(), g.xadj.data(), g.adj.data(), perm.data(), control, info, constraint.data()) == CAMD_OK);
  return perm;
}

}  // namespace

TEST_CASE("minimum degree: CAMD on the graph directly is camd_order's order; constraint sets in turn") {
  std::mt19937_64 rng(11);
  int checked = 0;
  for (const int32_t n : {2, 3, 17, 300, 1200}) {
    for (const int per_row : {1, 3, 8}) {
      const AdjacencyGraph g = n == 1200 && per_row == 8 ? adjacency_of(test::grid_laplacian(40, 30, 0.01))
                                                         : random_graph(n, per_row, rng());
      CAPTURE(n);
      CAPTURE(per_row);
      for (const int sets : {1, 2, 3}) {
        if (sets > g.n()) continue;  // CAMD's constraint values are below n
        HostVector<int32_t> constraint(static_cast<size_t>(g.n()));
        for (int32_t& c : constraint) c = static_cast<int32_t>(rng() % sets);
        const HostVector<int32_t> got = constrained_minimum_degree_order(g, constraint);
        CHECK(got == camd_order_of(g, constraint));
        std::vector<int32_t> seen(got.begin(), got.end());
        std::sort(seen.begin(), seen.end());
        for (int32_t k = 0; k < g.n(); ++k) REQUIRE(seen[k] == k);
        for (int32_t k = 1; k < g.n(); ++k) CHECK(constraint[got[k - 1]] <= constraint[got[k]]);
        ++checked;
      }
    }
  }
  CHECK(checked == 42);
}

TEST_CASE("minimum degree: a graph without edges comes back set by set, in index order") {
  AdjacencyGraph g;
  g.xadj.assign(6, 0);  // 5 vertices, no edges
  const HostVector<int32_t> constraint{1, 0, 2, 0, 1};
  const HostVector<int32_t> got = constrained_minimum_degree_order(g, constraint);
  CHECK(got == HostVector<int32_t>{1, 3, 0, 4, 2});
  CHECK(minimum_degree_order(g) == HostVector<int32_t>{0, 1, 2, 3, 4});
}

TEST_CASE("minimum degree: constraints of the wrong count or outside [0, n) are a usage error") {
  const AdjacencyGraph g = random_graph(10, 2, 3);
  CHECK_THROWS_AS(constrained_minimum_degree_order(g, HostVector<int32_t>(9, 0)), Error);
  HostVector<int32_t> bad(10, 0);
  bad[4] = 10;
  CHECK_THROWS_WITH_AS(constrained_minimum_degree_order(g, bad),
                       doctest::Contains("constraint 10 of vertex 4 is outside [0, 10)"), Error);
  bad[4] = -1;
  CHECK_THROWS_AS(constrained_minimum_degree_order(g, bad), Error);
}
