// The shared coarsening's matching (graph_coarsening.hpp; thesis §4.2): one round is a maximal matching along the graph's edges (checked
// against the graph, edge by edge), and the map is the same for any thread
// count on a graph large enough for the parallel rounds, blocks and
// contractions, numbered non-locally as a subdivided mesh is.
#include "locus/kernels/order/graph_coarsening.hpp"

#include <doctest/doctest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

// g with vertex v renamed to label[v] (rows ascending again).
AdjacencyGraph relabeled(const AdjacencyGraph& g, const std::vector<int32_t>& label) {
  const int32_t n = g.n();
  std::vector<std::vector<int32_t>> rows(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v)
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) rows[label[v]].push_back(label[g.adj[p]]);
  AdjacencyGraph h;
  for (auto& r : rows) {
    std::sort(r.begin(), r.end());
    h.adj.insert(h.adj.end(), r.begin(), r.end());
    h.xadj.push_back(static_cast<int32_t>(h.adj.size()));
  }
  return h;
}

AdjacencyGraph scattered_grid(int nx, int ny, uint64_t seed) {
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(nx, ny, 0.01));
  std::vector<int32_t> label(static_cast<size_t>(g.n()));
  for (int32_t v = 0; v < g.n(); ++v) label[v] = v;
  std::mt19937_64 rng(seed);
  std::shuffle(label.begin(), label.end(), rng);
  return relabeled(g, label);
}

// A star (center 0, leaves 1..k) with a path k+1..n-1 hanging from leaf 1:
// one high-degree row, and vertices that can only stay single.
AdjacencyGraph star_and_path(int32_t k, int32_t n) {
  std::vector<std::set<int32_t>> rows(static_cast<size_t>(n));
  const auto join = [&](int32_t a, int32_t b) {
    rows[a].insert(b);
    rows[b].insert(a);
  };
  for (int32_t v = 1; v <= k; ++v) join(0, v);
  join(1, k + 1);
  for (int32_t v = k + 1; v + 1 < n; ++v) join(v, v + 1);
  AdjacencyGraph g;
  for (const auto& r : rows) {
    g.adj.insert(g.adj.end(), r.begin(), r.end());
    g.xadj.push_back(static_cast<int32_t>(g.adj.size()));
  }
  return g;
}

}  // namespace

TEST_CASE("coarsening: one round is a maximal matching along the graph's edges") {
  AdjacencyGraph no_edges;
  for (int v = 0; v < 10; ++v) no_edges.xadj.push_back(0);
  const std::vector<AdjacencyGraph> graphs{adjacency_of(test::grid_laplacian(60, 50, 0.01)), scattered_grid(60, 50, 3),
                                           adjacency_of(test::random_spd(3000, 6, 11)), star_and_path(300, 700),
                                           no_edges, AdjacencyGraph{}};
  for (size_t k = 0; k < graphs.size(); ++k) {
    CAPTURE(k);
    const AdjacencyGraph& g = graphs[k];
    const int32_t n = g.n();
    HostVector<int32_t> cmap;
    const int32_t nc = coarsening_map(g, 1, cmap);
    REQUIRE(cmap.size() == static_cast<size_t>(n));
    std::vector<std::vector<int32_t>> group(static_cast<size_t>(nc));
    for (int32_t v = 0; v < n; ++v) {
      REQUIRE(cmap[v] >= 0);
      REQUIRE(cmap[v] < nc);
      group[cmap[v]].push_back(v);
    }
    const auto adjacent = [&g](int32_t a, int32_t b) {
      return std::binary_search(g.adj.begin() + g.xadj[a], g.adj.begin() + g.xadj[a + 1], b);
    };
    bool sizes_ok = true, pairs_adjacent = true;
    for (const auto& members : group) {
      sizes_ok = sizes_ok && (members.size() == 1 || members.size() == 2);
      if (members.size() == 2) pairs_adjacent = pairs_adjacent && adjacent(members[0], members[1]);
    }
    CHECK(sizes_ok);
    CHECK(pairs_adjacent);
    // Maximal: no edge joins two vertices left single.
    bool maximal = true;
    for (int32_t v = 0; v < n; ++v)
      for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
        maximal = maximal && !(group[cmap[v]].size() == 1 && group[cmap[g.adj[p]]].size() == 1);
    CHECK(maximal);
    // Coarse vertices are numbered in the order of their lowest vertex.
    bool ordered = true;
    for (int32_t c = 1; c < nc; ++c) ordered = ordered && group[c - 1][0] < group[c][0];
    CHECK(ordered);
  }
  // The star's center takes one leaf; the other leaves stay single.
  HostVector<int32_t> cmap;
  const int32_t nc = coarsening_map(star_and_path(300, 700), 1, cmap);
  CHECK(std::count(cmap.begin(), cmap.begin() + 301, cmap[0]) == 2);
  CHECK(nc >= 299 + 200);
}

TEST_CASE("coarsening: the same map for 1, 2, 3 and 8 threads on a scattered 230 x 230 grid") {
  // 52 900 vertices: many rounds' parallel ranges, numbering blocks and
  // contraction blocks; shuffled labels make every row's reads non-local.
  const AdjacencyGraph g = scattered_grid(230, 230, 5);
  for (const int levels : {1, 3, 5}) {
    CAPTURE(levels);
    HostVector<int32_t> ref;
    int32_t nc = 0;
    tbb::task_arena(1).execute([&] { nc = coarsening_map(g, levels, ref); });
    CHECK(nc < g.n() * (levels == 1 ? 0.6 : levels == 3 ? 0.2 : 0.06));
    for (const int threads : {2, 3, 8}) {
      CAPTURE(threads);
      HostVector<int32_t> got;
      int32_t got_nc = 0;
      tbb::task_arena(threads).execute([&] { got_nc = coarsening_map(g, levels, got); });
      CHECK(got_nc == nc);
      CHECK(got == ref);
    }
  }
}

TEST_CASE("coarsening: the last level's graph given with the map is contract_graph's, for 1, 2 and 8 threads") {
  // contract_graph along the map is the oracle (itself checked against a
  // brute-force set construction in separator_refinement.cpp): the same
  // neighbors with the same weights in every row, the order aside.
  const AdjacencyGraph g = scattered_grid(120, 90, 9);
  for (const int levels : {1, 2, 5}) {
    CAPTURE(levels);
    HostVector<int32_t> cmap;
    const int32_t nc = coarsening_map(g, levels, cmap);
    HostVector<int32_t> vwgt, ewgt;
    const AdjacencyGraph want = contract_graph(g, cmap, nc, vwgt, &ewgt);
    const auto rows = [](const AdjacencyGraph& h, const HostVector<int32_t>& w) {
      std::vector<std::vector<std::pair<int32_t, int32_t>>> r(static_cast<size_t>(h.n()));
      for (int32_t c = 0; c < h.n(); ++c) {
        for (int32_t p = h.xadj[c]; p < h.xadj[c + 1]; ++p) r[c].emplace_back(h.adj[p], w[p]);
        std::sort(r[c].begin(), r[c].end());
      }
      return r;
    };
    const auto want_rows = rows(want, ewgt);
    for (const int threads : {1, 2, 8}) {
      CAPTURE(threads);
      HostVector<int32_t> got_map;
      Contraction top;
      int32_t got_nc = 0;
      tbb::task_arena(threads).execute([&] { got_nc = coarsening_map(g, levels, got_map, nullptr, &top); });
      CHECK(got_nc == nc);
      CHECK(got_map == cmap);  // asking for the graph does not change the map
      REQUIRE(top.graph.n() == nc);
      REQUIRE(top.ewgt.size() == top.graph.adj.size());
      CHECK(rows(top.graph, top.ewgt) == want_rows);
    }
  }
}
