// Level-structure separators (level_separator.hpp) against separators known
// by hand: the middle of a path, a diagonal of a grid, the vertex next to a
// heavy end; and the graphs it must hand back to METIS.
#include "locus/kernels/order/level_separator.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace locus;

namespace {

AdjacencyGraph graph_of(int32_t n, const std::vector<std::pair<int32_t, int32_t>>& edges) {
  std::vector<std::set<int32_t>> rows(static_cast<size_t>(n));
  for (const auto& [a, b] : edges) {
    rows[a].insert(b);
    rows[b].insert(a);
  }
  AdjacencyGraph g;
  g.xadj.assign(1, 0);
  for (const auto& r : rows) {
    g.adj.insert(g.adj.end(), r.begin(), r.end());
    g.xadj.push_back(static_cast<int32_t>(g.adj.size()));
  }
  return g;
}

AdjacencyGraph path(int32_t n) {
  std::vector<std::pair<int32_t, int32_t>> e;
  for (int32_t v = 0; v + 1 < n; ++v) e.emplace_back(v, v + 1);
  return graph_of(n, e);
}

AdjacencyGraph grid(int32_t nx, int32_t ny) {
  std::vector<std::pair<int32_t, int32_t>> e;
  for (int32_t y = 0; y < ny; ++y)
    for (int32_t x = 0; x < nx; ++x) {
      if (x + 1 < nx) e.emplace_back(y * nx + x, y * nx + x + 1);
      if (y + 1 < ny) e.emplace_back(y * nx + x, (y + 1) * nx + x);
    }
  return graph_of(nx * ny, e);
}

bool is_separator(const AdjacencyGraph& g, const HostVector<int8_t>& part) {
  for (int32_t v = 0; v < g.n(); ++v)
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (part[v] + part[g.adj[p]] == 1) return false;
  return true;
}

int32_t count_of(const HostVector<int8_t>& part, int8_t s) {
  return static_cast<int32_t>(std::count(part.begin(), part.end(), s));
}

}  // namespace

TEST_CASE("level separator: the middle vertex of a path; the vertex next to a heavy end") {
  HostVector<int8_t> part;
  REQUIRE(level_separator(path(9), {}, part));
  CHECK(part == HostVector<int8_t>{0, 0, 0, 0, 2, 1, 1, 1, 1});
  // Weights 10,1,1,1,1,1,1: no level leaves sides within 1.3x of even; the
  // best balance (10 against 5) puts vertex 1 in the separator.
  const std::vector<int32_t> w{10, 1, 1, 1, 1, 1, 1};
  REQUIRE(level_separator(path(7), w, part));
  CHECK(part == HostVector<int8_t>{0, 2, 1, 1, 1, 1, 1});
}

TEST_CASE("level separator: a grid is cut along a diagonal no longer than its short side, sides balanced") {
  for (const auto& dims : {std::pair{20, 10}, std::pair{31, 31}, std::pair{50, 7}}) {
    const int nx = dims.first, ny = dims.second;  // not bindings: CAPTURE takes them in a lambda
    CAPTURE(nx);
    CAPTURE(ny);
    const AdjacencyGraph g = grid(nx, ny);
    HostVector<int8_t> part;
    REQUIRE(level_separator(g, {}, part));
    CHECK(is_separator(g, part));
    const int32_t s0 = count_of(part, 0), s1 = count_of(part, 1), s = count_of(part, 2);
    CHECK(s <= std::min(nx, ny));
    CHECK(20 * std::max(s0, s1) <= 13 * (s0 + s1));
  }
}

TEST_CASE("level separator: disconnected or shallow graphs are handed back; random graphs get a valid separator") {
  HostVector<int8_t> part{7, 7};
  CHECK_FALSE(level_separator(graph_of(6, {{0, 1}, {1, 2}, {3, 4}, {4, 5}}), {}, part));
  CHECK(part == HostVector<int8_t>{7, 7});  // untouched
  CHECK_FALSE(level_separator(graph_of(4, {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}), {}, part));  // K4: 2 levels
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const int32_t n = 20 + static_cast<int32_t>(rng() % 200);
    std::vector<std::pair<int32_t, int32_t>> e;
    for (int32_t v = 1; v < n; ++v) e.emplace_back(v, static_cast<int32_t>(rng() % v));  // a random tree: connected
    for (int32_t k = 0; k < n / 2; ++k) e.emplace_back(rng() % n, rng() % n);
    e.erase(std::remove_if(e.begin(), e.end(), [](const auto& p) { return p.first == p.second; }), e.end());
    const AdjacencyGraph g = graph_of(n, e);
    if (!level_separator(g, {}, part)) continue;  // too shallow
    CHECK(is_separator(g, part));
    CHECK(count_of(part, 0) > 0);
    CHECK(count_of(part, 1) > 0);
    CHECK(count_of(part, 2) > 0);
  }
}
