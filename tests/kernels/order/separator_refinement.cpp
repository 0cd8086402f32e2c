// The pieces of the shared-coarsening nested dissection:
// FM refinement of a vertex separator (separator_refinement.hpp) against the
// analytic minimum separator of a grid, and the coarsening map and per-node
// contraction (graph_coarsening.hpp) against brute-force set constructions.
#include "locus/kernels/order/separator_refinement.hpp"

#include <doctest/doctest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <map>
#include <queue>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "locus/kernels/order/graph_coarsening.hpp"
#include "locus/kernels/order/metis_ordering.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

// No edge joins side 0 to side 1.
bool is_separator(const AdjacencyGraph& g, const HostVector<int8_t>& part) {
  for (int32_t v = 0; v < g.n(); ++v)
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (part[v] + part[g.adj[p]] == 1) return false;  // one 0 and one 1
  return true;
}

int32_t count_of(const HostVector<int8_t>& part, int8_t s) {
  return static_cast<int32_t>(std::count(part.begin(), part.end(), s));
}

// coarse[v] drawn uniformly from [0, nc): a map for the contraction tests.
HostVector<int32_t> random_coarse_map(int32_t n, int32_t nc, uint64_t seed) {
  std::mt19937_64 rng(seed);
  HostVector<int32_t> coarse(static_cast<size_t>(n));
  for (int32_t& c : coarse) c = static_cast<int32_t>(rng() % nc);
  return coarse;
}

// The refinement as its header states it, written the plain way: every gain
// recounted from the neighbors whenever it may have changed, the queue a
// binary heap of (gain, push count, vertex). The library keeps gains
// incrementally in a bucket queue; both must make the same moves.
int32_t reference_refinement(const AdjacencyGraph& g, HostVector<int8_t>& part, const SeparatorRefinementOptions& opt) {
  const int32_t n = g.n();
  std::vector<int32_t> gain(static_cast<size_t>(n)), stamp(static_cast<size_t>(n), -1);
  int32_t pw[3] = {0, 0, 0};
  std::vector<int32_t> sep;  // the separator, in the order the passes push it
  for (int32_t v = 0; v < n; ++v) {
    ++pw[part[v]];
    if (part[v] == 2) sep.push_back(v);
  }
  std::priority_queue<std::tuple<int32_t, int64_t, int32_t>> heap;
  int64_t pushes = 0;
  const auto balanced = [&](int32_t a, int32_t b) { return std::max(a, b) <= opt.max_imbalance * 0.5 * (a + b); };
  const auto push = [&](int32_t v, int8_t other, int pass) {
    if (stamp[v] == pass) return;
    int32_t k = 0;
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) k += part[g.adj[p]] == other;
    gain[v] = 1 - k;
    heap.emplace(gain[v], ++pushes, v);
  };
  int bad = 0;
  int8_t to = pw[0] <= pw[1] ? 0 : 1;
  for (int pass = 0; pass < opt.passes && bad < 2 && pw[2] > 0; ++pass, to = static_cast<int8_t>(1 - to)) {
    const int8_t other = static_cast<int8_t>(1 - to);
    heap = {};
    for (const int32_t v : sep) push(v, other, pass);
    const int32_t start = pw[2];
    int32_t best = pw[2], best_diff = std::abs(pw[0] - pw[1]), since = 0;
    bool best_bal = balanced(pw[0], pw[1]);
    std::vector<std::pair<int32_t, std::vector<int32_t>>> moves;  // (moved, pulled)
    size_t best_len = 0;
    const int32_t patience = std::clamp(2 * start, 20, opt.patience), stretched = opt.stretch * patience;
    while (!heap.empty() && since <= stretched && (since <= patience || 10 * pw[2] <= 11 * best)) {
      const auto [gn, tie, v] = heap.top();
      heap.pop();
      if (part[v] != 2 || stamp[v] == pass || gain[v] != gn) continue;
      const int32_t k = 1 - gn;
      stamp[v] = pass;
      if (!balanced(pw[to] + 1, pw[other] - k) && pw[to] + 1 > pw[other] - k) continue;
      part[v] = to;
      moves.push_back({v, {}});
      for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
        if (part[g.adj[p]] == other) { part[g.adj[p]] = 2; moves.back().second.push_back(g.adj[p]); }
      pw[to] += 1;
      pw[other] -= k;
      pw[2] += k - 1;
      for (const int32_t w : moves.back().second) {
        push(w, other, pass);
        for (int32_t p = g.xadj[w]; p < g.xadj[w + 1]; ++p)
          if (part[g.adj[p]] == 2 && stamp[g.adj[p]] != pass) push(g.adj[p], other, pass);
      }
      const bool bal = balanced(pw[0], pw[1]);
      const int32_t diff = std::abs(pw[0] - pw[1]);
      if ((bal && !best_bal) || (bal == best_bal && (pw[2] < best || (pw[2] == best && diff < best_diff)))) {
        best = pw[2], best_diff = diff, best_bal = bal, best_len = moves.size(), since = 0;
      } else {
        ++since;
      }
    }
    for (; moves.size() > best_len; moves.pop_back()) {
      for (const int32_t w : moves.back().second) part[w] = other;
      const int32_t k = static_cast<int32_t>(moves.back().second.size());
      part[moves.back().first] = 2;
      pw[to] -= 1, pw[other] += k, pw[2] -= k - 1;
    }
    // Next pass' order: the old separator's vertices still in it, then the pulled ones.
    std::vector<int32_t> next;
    for (const int32_t v : sep)
      if (part[v] == 2) next.push_back(v);
    for (const auto& m : moves)
      for (const int32_t w : m.second)
        if (part[w] == 2) next.push_back(w);
    sep = std::move(next);
    bad = pw[2] < start ? 0 : bad + 1;
  }
  return pw[2];
}

}  // namespace

TEST_CASE("separator refinement: a thick jagged band on a grid thins to one column, the minimum") {
  // 5-point grid nx x ny: a balanced vertex separator has at least ny
  // vertices (one per row), and a straight column has exactly ny.
  const int nx = 40, ny = 30;
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(nx, ny, 0.01));
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 5; ++trial) {
    HostVector<int8_t> part(static_cast<size_t>(nx * ny));
    for (int y = 0; y < ny; ++y) {
      const int lo = 15 + static_cast<int>(rng() % 3), hi = 21 + static_cast<int>(rng() % 3);  // band lo..hi, jagged
      for (int x = 0; x < nx; ++x) part[y * nx + x] = x < lo ? 0 : x <= hi ? 2 : 1;
    }
    REQUIRE(is_separator(g, part));
    const int32_t before = count_of(part, 2);
    const int32_t after = refine_vertex_separator(g, part);
    CHECK(after == count_of(part, 2));
    CHECK(is_separator(g, part));
    CHECK(after == ny);
    CHECK(after < before);
    // Balanced as asked: each side at most max_imbalance x half of the rest.
    const int32_t a = count_of(part, 0), b = count_of(part, 1);
    CHECK(std::max(a, b) <= SeparatorRefinementOptions{}.max_imbalance * 0.5 * (a + b));
  }
}

TEST_CASE("separator refinement: a minimum separator stays as it is; no separator stays none") {
  const int nx = 20, ny = 12;
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(nx, ny, 0.01));
  HostVector<int8_t> part(static_cast<size_t>(nx * ny));
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) part[y * nx + x] = x < 10 ? 0 : x == 10 ? 2 : 1;
  CHECK(refine_vertex_separator(g, part) == ny);
  CHECK(is_separator(g, part));
  HostVector<int8_t> none(static_cast<size_t>(nx * ny), 0);
  CHECK(refine_vertex_separator(g, none) == 0);
  CHECK(count_of(none, 0) == nx * ny);
}

TEST_CASE("coarsening: every coarse vertex is a connected group of at most 2^levels vertices; deterministic") {
  for (const CscMatrix& A : {test::grid_laplacian(37, 23, 0.01), test::random_spd(3000, 6, 11)}) {
    const AdjacencyGraph g = adjacency_of(A);
    for (int levels : {1, 2, 3}) {
      CAPTURE(levels);
      HostVector<int32_t> cmap;
      const int32_t nc = coarsening_map(g, levels, cmap);
      REQUIRE(cmap.size() == static_cast<size_t>(g.n()));
      std::vector<std::vector<int32_t>> group(static_cast<size_t>(nc));
      for (int32_t v = 0; v < g.n(); ++v) {
        REQUIRE(cmap[v] >= 0);
        REQUIRE(cmap[v] < nc);
        group[cmap[v]].push_back(v);
      }
      for (const auto& members : group) {
        REQUIRE(!members.empty());
        CHECK(members.size() <= (size_t{1} << levels));
        // Connected inside g (a matching merges only neighbors).
        std::set<int32_t> reached{members[0]}, in(members.begin(), members.end());
        std::vector<int32_t> stack{members[0]};
        while (!stack.empty()) {
          const int32_t v = stack.back();
          stack.pop_back();
          for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
            if (in.count(g.adj[p]) && reached.insert(g.adj[p]).second) stack.push_back(g.adj[p]);
        }
        CHECK(reached.size() == members.size());
      }
      // A matching round at least nearly halves a grid or a random graph.
      CHECK(nc <= g.n() * (levels == 1 ? 0.6 : levels == 2 ? 0.4 : 0.25));
      HostVector<int32_t> again;
      CHECK(coarsening_map(g, levels, again) == nc);
      CHECK(again == cmap);
    }
  }
}

TEST_CASE("coarsening: the contraction of a graph is the set of its coarse edges, with the right weights") {
  const AdjacencyGraph g = adjacency_of(test::random_spd(500, 5, 4));
  const int32_t nc = 90;
  const HostVector<int32_t> coarse = random_coarse_map(g.n(), nc, 8);
  HostVector<int32_t> vwgt;
  HostVector<int32_t> ewgt;
  const AdjacencyGraph h = contract_graph(g, coarse, nc, vwgt, &ewgt);
  REQUIRE(h.n() == nc);
  REQUIRE(ewgt.size() == h.adj.size());
  // Edge weights: the fine edges (directed entries of g) from c's vertices to d's.
  std::map<std::pair<int32_t, int32_t>, int32_t> want_e;
  for (int32_t v = 0; v < g.n(); ++v)
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (coarse[g.adj[p]] != coarse[v]) ++want_e[{coarse[v], coarse[g.adj[p]]}];
  for (int32_t c = 0; c < nc; ++c)
    for (int32_t p = h.xadj[c]; p < h.xadj[c + 1]; ++p) CHECK(ewgt[p] == want_e[{c, h.adj[p]}]);
  std::vector<std::set<int32_t>> want(static_cast<size_t>(nc));
  std::vector<int32_t> want_w(static_cast<size_t>(nc), 0);
  for (int32_t v = 0; v < g.n(); ++v) {
    ++want_w[coarse[v]];
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (coarse[g.adj[p]] != coarse[v]) want[coarse[v]].insert(coarse[g.adj[p]]);
  }
  for (int32_t c = 0; c < nc; ++c) {
    const std::set<int32_t> got(h.adj.begin() + h.xadj[c], h.adj.begin() + h.xadj[c + 1]);
    CHECK(got == want[c]);
    CHECK(static_cast<size_t>(h.degree(c)) == want[c].size());  // no duplicates
    CHECK(vwgt[c] == want_w[c]);
  }
}

TEST_CASE("coarsening: a subgraph's contraction cut out of the whole one holds the exact one and only edges of the whole") {
  // A grid, coarsened for real, and a subgraph: one side of a jagged cut
  // (what a child of the nested dissection is). The exact contraction of the
  // subgraph is built by brute force from the subgraph's own edges.
  const int nx = 60, ny = 40;
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(nx, ny, 0.01));
  HostVector<int32_t> cmap;
  const int32_t nc = coarsening_map(g, 3, cmap);
  HostVector<int32_t> vwgt, ewgt;
  const AdjacencyGraph h = contract_graph(g, cmap, nc, vwgt, &ewgt);
  std::mt19937_64 rng(12);
  std::vector<bool> in(static_cast<size_t>(g.n()));
  for (int y = 0; y < ny; ++y) {
    const int cut = 25 + static_cast<int>(rng() % 7);
    for (int x = 0; x < nx; ++x) in[y * nx + x] = x < cut;
  }
  HostVector<int32_t> keep(static_cast<size_t>(nc), -1);
  int32_t nkept = 0;
  for (int32_t v = 0; v < g.n(); ++v)
    if (in[v] && keep[cmap[v]] < 0) keep[cmap[v]] = nkept++;
  HostVector<int32_t> kept_ewgt;
  const AdjacencyGraph r = restrict_contraction(h, keep, nkept, ewgt, &kept_ewgt);
  REQUIRE(r.n() == nkept);
  REQUIRE(kept_ewgt.size() == r.adj.size());
  std::set<std::pair<int32_t, int32_t>> exact, whole, got;
  for (int32_t v = 0; v < g.n(); ++v)
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) {
      const int32_t w = g.adj[p], a = keep[cmap[v]], b = keep[cmap[w]];
      if (cmap[v] == cmap[w] || a < 0 || b < 0) continue;
      whole.insert({a, b});  // joined in the whole graph, both kept
      if (in[v] && in[w]) exact.insert({a, b});
    }
  for (int32_t a = 0; a < nkept; ++a)
    for (int32_t p = r.xadj[a]; p < r.xadj[a + 1]; ++p) CHECK(got.insert({a, r.adj[p]}).second);  // no duplicates
  CHECK(std::includes(got.begin(), got.end(), exact.begin(), exact.end()));
  CHECK(got == whole);
  CHECK(exact.size() < got.size());  // the cut did drop some: the test sees the difference
  // Weights: the whole contraction's.
  for (int32_t a = 0, c = 0; c < nc; ++c) {
    if (keep[c] < 0) continue;
    a = keep[c];
    std::map<int32_t, int32_t> w;
    for (int32_t p = h.xadj[c]; p < h.xadj[c + 1]; ++p)
      if (keep[h.adj[p]] >= 0) w[keep[h.adj[p]]] = ewgt[p];
    for (int32_t p = r.xadj[a]; p < r.xadj[a + 1]; ++p) CHECK(kept_ewgt[p] == w[r.adj[p]]);
  }
}

TEST_CASE("METIS vertex separator with vertex and edge weights: a balanced separator of the contraction") {
  const int nx = 80, ny = 60;
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(nx, ny, 0.01));
  HostVector<int32_t> cmap;
  const int32_t nc = coarsening_map(g, 3, cmap);
  HostVector<int32_t> vwgt, ewgt;
  const AdjacencyGraph h = contract_graph(g, cmap, nc, vwgt, &ewgt);
  HostVector<int8_t> part, plain;
  metis_vertex_separator(h, 7, part, nullptr, vwgt, ewgt);
  metis_vertex_separator(h, 7, plain, nullptr, vwgt);
  for (const HostVector<int8_t>* p : {&part, &plain}) {
    REQUIRE(p->size() == static_cast<size_t>(nc));
    CHECK(is_separator(h, *p));
    int64_t w[3] = {0, 0, 0};
    for (int32_t c = 0; c < nc; ++c) w[(*p)[c]] += vwgt[c];
    // Weighted balance (METIS' 1.2 of half the total, plus a coarse vertex
    // of slack), and a short separator: a grid's minimum is ny = 60 fine
    // vertices; a projected coarse one is a few of them thick.
    CHECK(std::max(w[0], w[1]) <= 0.6 * nx * ny + 8);
    CHECK(w[2] > 0);
    CHECK(w[2] <= 6 * ny);
  }
}

TEST_CASE("separator refinement: the same moves as the plain way (gains recounted, a binary heap)") {
  // Rough separators of grids: a jagged band, and the outer layer of a
  // ball of a BFS (a rounded, wrongly placed cut that FM must move).
  std::vector<std::pair<AdjacencyGraph, HostVector<int8_t>>> cases;
  const int nx = 70, ny = 50;
  {
    AdjacencyGraph g = adjacency_of(test::grid_laplacian(nx, ny, 0.01));
    std::mt19937_64 rng(5);
    HostVector<int8_t> part(static_cast<size_t>(nx * ny));
    for (int y = 0; y < ny; ++y) {
      const int lo = 20 + static_cast<int>(rng() % 4), hi = 26 + static_cast<int>(rng() % 6);
      for (int x = 0; x < nx; ++x) part[y * nx + x] = x < lo ? 0 : x <= hi ? 2 : 1;
    }
    REQUIRE(is_separator(g, part));
    cases.emplace_back(std::move(g), std::move(part));
  }
  for (const int32_t seed : {0, 1234, 3012}) {
    AdjacencyGraph g = adjacency_of(test::grid_laplacian(nx, ny, 0.01));
    std::vector<int32_t> dist(static_cast<size_t>(g.n()), -1), queue{seed};
    dist[seed] = 0;
    for (size_t q = 0; q < queue.size() && 2 * q < static_cast<size_t>(g.n()); ++q)
      for (int32_t p = g.xadj[queue[q]]; p < g.xadj[queue[q] + 1]; ++p)
        if (dist[g.adj[p]] < 0) { dist[g.adj[p]] = dist[queue[q]] + 1; queue.push_back(g.adj[p]); }
    const int32_t r = dist[queue.back()];
    HostVector<int8_t> part(static_cast<size_t>(g.n()));
    for (int32_t v = 0; v < g.n(); ++v) part[v] = dist[v] < 0 || dist[v] > r ? 1 : dist[v] >= r - 1 ? 2 : 0;
    REQUIRE(is_separator(g, part));
    cases.emplace_back(std::move(g), std::move(part));
  }
  SeparatorRefinementOptions tight;
  tight.max_imbalance = 1.1;
  tight.patience = 40;
  // One workspace for all calls, as a thread of the nested dissection keeps
  // it: its marks from earlier (larger and smaller) graphs must not count.
  SeparatorRefinementWorkspace ws;
  for (int round = 0; round < 2; ++round)
    for (const auto& [g, start] : cases)
      for (const SeparatorRefinementOptions& opt : {SeparatorRefinementOptions{}, tight}) {
        HostVector<int8_t> got = start, again = start, want = start;
        const int32_t got_size = refine_vertex_separator(g, got, opt);
        const int32_t again_size = refine_vertex_separator(g, again, opt, &ws);
        const int32_t want_size = reference_refinement(g, want, opt);
        CHECK(got_size == want_size);
        CHECK(got == want);
        CHECK(again_size == want_size);
        CHECK(again == want);
        CHECK(got_size < count_of(start, 2));  // the refinement did move vertices: the comparison sees them
        CHECK(is_separator(g, got));
      }
}

TEST_CASE("coarsening: a contraction of many blocks is the brute-force one, for 1, 2 and 8 threads") {
  // More coarse vertices than a few of the contraction's parallel blocks:
  // every row holds its coarse neighbors in order of first appearance
  // (members ascending, each one's list in order), with the summed weights.
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(180, 150, 0.01));
  const int32_t nc = 11000;
  const HostVector<int32_t> coarse = random_coarse_map(g.n(), nc, 9);
  std::vector<std::vector<int32_t>> want(static_cast<size_t>(nc)), want_w(static_cast<size_t>(nc));
  for (int32_t v = 0; v < g.n(); ++v)  // v ascending: members of each coarse vertex ascending
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) {
      const int32_t c = coarse[v], d = coarse[g.adj[p]];
      if (c == d) continue;
      const auto it = std::find(want[c].begin(), want[c].end(), d);
      if (it == want[c].end()) {
        want[c].push_back(d);
        want_w[c].push_back(1);
      } else {
        ++want_w[c][it - want[c].begin()];
      }
    }
  for (const int threads : {1, 2, 8}) {
    CAPTURE(threads);
    HostVector<int32_t> vwgt, ewgt;
    AdjacencyGraph h;
    tbb::task_arena(threads).execute([&] { h = contract_graph(g, coarse, nc, vwgt, &ewgt); });
    REQUIRE(h.n() == nc);
    REQUIRE(ewgt.size() == h.adj.size());
    bool same = true;
    for (int32_t c = 0; c < nc; ++c) {
      same = same && std::vector<int32_t>(h.adj.begin() + h.xadj[c], h.adj.begin() + h.xadj[c + 1]) == want[c];
      same = same && std::vector<int32_t>(ewgt.begin() + h.xadj[c], ewgt.begin() + h.xadj[c + 1]) == want_w[c];
    }
    CHECK(same);
  }
}
