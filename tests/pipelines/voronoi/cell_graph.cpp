// Tests for pipelines/voronoi/cell_graph.{hpp,cpp}. Oracles: cell lists and cell
// adjacency rebuilt from the faces with std::set (two cells are adjacent when a
// triangle side joins them); the batch order of a strip of cells in a row
// derived by hand from the breadth-first rule.
#include "locus/pipelines/voronoi/cell_graph.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

using namespace locus;

namespace {

// Labels of a 20 x 20 grid by column bands of two: cells 0..9 in a row.
std::vector<int32_t> column_labels(const Mesh& m, int32_t bands) {
  std::vector<int32_t> label(static_cast<size_t>(m.num_vertices()));
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    label[v] = std::min(bands - 1, static_cast<int32_t>(m.x[v] * bands));
  return label;
}

}  // namespace

TEST_CASE("cell graph: cell lists and adjacency as rebuilt from the faces") {
  const Mesh m = make_random_sphere(800, 6);
  const int32_t ns = 25;
  std::mt19937 rng(4);
  std::vector<int32_t> label(static_cast<size_t>(m.num_vertices()));
  // Labels of the nearest of 25 random vertices (Euclidean): connected-ish cells,
  // some of them possibly empty or split, which the graph must not care about.
  std::vector<int32_t> centre(ns);
  for (int32_t& c : centre) c = static_cast<int32_t>(rng() % m.num_vertices());
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    double best = 1e300;
    for (int32_t s = 0; s < ns; ++s) {
      const int32_t c = centre[s];
      const double d = (m.x[v] - m.x[c]) * (m.x[v] - m.x[c]) + (m.y[v] - m.y[c]) * (m.y[v] - m.y[c]) +
                       (m.z[v] - m.z[c]) * (m.z[v] - m.z[c]);
      if (d < best) best = d, label[v] = s;
    }
  }
  const CellGraph by_edges = build_cell_graph(unique_edges(m), label, ns);
  const CellGraph by_adjacency = build_cell_graph(vertex_adjacency(m), label, ns);
  std::vector<std::set<int32_t>> want_adj(ns);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int a = 0; a < 3; ++a) {
      const int32_t la = label[v[a]], lb = label[v[(a + 1) % 3]];
      if (la != lb) {
        want_adj[la].insert(lb);
        want_adj[lb].insert(la);
      }
    }
  }
  for (const CellGraph* graph : {&by_edges, &by_adjacency}) {
    const CellGraph& g = *graph;
    REQUIRE(g.offsets.size() == static_cast<size_t>(ns) + 1);
    REQUIRE(g.adj_offsets.size() == static_cast<size_t>(ns) + 1);
    for (int32_t s = 0; s < ns; ++s) {
      std::vector<int32_t> want_verts;
      for (int32_t v = 0; v < m.num_vertices(); ++v)
        if (label[v] == s) want_verts.push_back(v);
      CHECK(std::vector<int32_t>(g.verts.begin() + g.offsets[s], g.verts.begin() + g.offsets[s + 1]) == want_verts);
      CHECK(std::vector<int32_t>(g.adj.begin() + g.adj_offsets[s], g.adj.begin() + g.adj_offsets[s + 1]) ==
            std::vector<int32_t>(want_adj[s].begin(), want_adj[s].end()));
    }
    // Two rings of cell 0, as vertices: every vertex of the cells within two steps.
    std::vector<int32_t> cells;
    append_two_ring_cells(g, 0, cells);
    std::set<int32_t> ring{0};
    for (int32_t a : want_adj[0]) {
      ring.insert(a);
      ring.insert(want_adj[a].begin(), want_adj[a].end());
    }
    HostVector<int32_t> verts;
    cells_to_vertices(g, cells, verts);
    CHECK(cells == std::vector<int32_t>(ring.begin(), ring.end()));
    std::vector<int32_t> want;
    for (int32_t v = 0; v < m.num_vertices(); ++v)
      if (ring.count(label[v])) want.push_back(v);
    std::vector<int32_t> got(verts.begin(), verts.end());
    std::sort(got.begin(), got.end());
    CHECK(got == want);
    // Appended after what `verts` held: the same list behind it.
    HostVector<int32_t> appended{-7};
    std::vector<int32_t> again;
    append_two_ring_cells(g, 0, again);
    append_cells_vertices(g, again, appended);
    REQUIRE(appended.size() == verts.size() + 1);
    CHECK(appended[0] == -7);
    CHECK(std::equal(verts.begin(), verts.end(), appended.begin() + 1));
  }
}

TEST_CASE("cell graph: batches of neighboring cells on a row of cells") {
  const Mesh m = make_grid(20);
  const std::vector<int32_t> label = column_labels(m, 10);
  const CellGraph g = build_cell_graph(unique_edges(m), label, 10);
  // Cells in a row: 0 - 1 - ... - 9. From cell 5, breadth-first in batches of 4:
  // 5, then 4 and 6, then 3 (4's neighbor) fill the first; the next starts at the
  // first untaken cell of the seed order (0) and runs 0, 1, 2, then, its patch
  // exhausted, restarts at 7; the last batch is 8, 9.
  const std::vector<int32_t> seed = {5, 0, 1, 2, 3, 4, 6, 7, 8, 9};
  CHECK(cluster_order(g, seed, 4) == std::vector<int32_t>{5, 4, 6, 3, 0, 1, 2, 7, 8, 9});
  // Batches of 1 follow the seed order.
  CHECK(cluster_order(g, seed, 1) == seed);
  // One batch of everything: breadth-first from 5 over the whole row.
  CHECK(cluster_order(g, seed, 10) == std::vector<int32_t>{5, 4, 6, 3, 7, 2, 8, 1, 9, 0});
}
