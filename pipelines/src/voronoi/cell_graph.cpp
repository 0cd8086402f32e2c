// Cells of a labelling, their adjacency graph and batches of neighboring cells
// (pipelines/include/locus/pipelines/voronoi/cell_graph.hpp; thesis §3.6-3.7.1).
#include "locus/pipelines/voronoi/cell_graph.hpp"
#include "locus/core/host_allocator.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>

namespace locus {

namespace {

// The vertices of each cell (CSR, ascending: one counting pass over the labels).
void bucket_vertices(std::span<const int32_t> label, int32_t ns, CellGraph& c) {
  c.offsets.assign(static_cast<size_t>(ns) + 1, 0);
  for (int32_t l : label) ++c.offsets[l + 1];
  for (int32_t s = 0; s < ns; ++s) c.offsets[s + 1] += c.offsets[s];
  c.verts.resize(label.size());
  std::vector<int64_t> fill(c.offsets.begin(), c.offsets.end() - 1);
  for (size_t v = 0; v < label.size(); ++v) c.verts[fill[label[v]]++] = static_cast<int32_t>(v);
}

// The graph from every edge (a, b) that `for_each_edge` visits, in any order:
// the labels across the edges between two cells, bucketed by cell (CSR with
// repeats), then sorted and deduplicated per cell in parallel.
template <class ForEachEdge>
CellGraph cell_graph_of(ForEachEdge&& for_each_edge, std::span<const int32_t> label, int32_t ns) {
  CellGraph c;
  bucket_vertices(label, ns, c);
  std::vector<int64_t> raw_off(static_cast<size_t>(ns) + 1, 0);
  for_each_edge([&](int32_t u, int32_t v) {
    const int32_t a = label[u], b = label[v];
    if (a != b) {
      ++raw_off[a + 1];
      ++raw_off[b + 1];
    }
  });
  for (int32_t s = 0; s < ns; ++s) raw_off[s + 1] += raw_off[s];
  HostVector<int32_t> raw(static_cast<size_t>(raw_off[ns]));
  std::vector<int64_t> fill(raw_off.begin(), raw_off.end() - 1);
  for_each_edge([&](int32_t u, int32_t v) {
    const int32_t a = label[u], b = label[v];
    if (a != b) {
      raw[fill[a]++] = b;
      raw[fill[b]++] = a;
    }
  });
  std::vector<int64_t> count(ns);
  tbb::parallel_for(0, ns, [&](int32_t s) {
    auto first = raw.begin() + raw_off[s], last = raw.begin() + raw_off[s + 1];
    std::sort(first, last);
    count[s] = std::unique(first, last) - first;
  });
  c.adj_offsets.assign(static_cast<size_t>(ns) + 1, 0);
  for (int32_t s = 0; s < ns; ++s) c.adj_offsets[s + 1] = c.adj_offsets[s] + count[s];
  c.adj.resize(static_cast<size_t>(c.adj_offsets[ns]));
  for (int32_t s = 0; s < ns; ++s)
    std::copy(raw.begin() + raw_off[s], raw.begin() + raw_off[s] + count[s], c.adj.begin() + c.adj_offsets[s]);
  return c;
}

}  // namespace

CellGraph build_cell_graph(const Edges& edges, std::span<const int32_t> label, int32_t ns) {
  return cell_graph_of(
      [&](auto&& visit) {
        for (size_t k = 0; k < edges.e0.size(); ++k) visit(edges.e0[k], edges.e1[k]);
      },
      label, ns);
}

CellGraph build_cell_graph(const Adjacency& adj, std::span<const int32_t> label, int32_t ns) {
  const int32_t n = static_cast<int32_t>(label.size());
  return cell_graph_of(
      [&](auto&& visit) {  // each edge once, from its smaller end
        for (int32_t u = 0; u < n; ++u)
          for (int64_t p = adj.offsets[u]; p < adj.offsets[u + 1]; ++p)
            if (adj.neighbors[p] > u) visit(u, adj.neighbors[p]);
      },
      label, ns);
}

void append_two_ring_cells(const CellGraph& c, int32_t s, std::vector<int32_t>& out) {
  out.push_back(s);
  for (int64_t p = c.adj_offsets[s]; p < c.adj_offsets[s + 1]; ++p) {
    const int32_t a = c.adj[p];
    out.push_back(a);
    for (int64_t q = c.adj_offsets[a]; q < c.adj_offsets[a + 1]; ++q) out.push_back(c.adj[q]);
  }
}

void cells_to_vertices(const CellGraph& c, std::vector<int32_t>& cells, HostVector<int32_t>& verts) {
  verts.clear();
  append_cells_vertices(c, cells, verts);
}

void append_cells_vertices(const CellGraph& c, std::vector<int32_t>& cells, HostVector<int32_t>& verts) {
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  // Cells are disjoint: the concatenation is already unique (the solve plan needs no order).
  for (int32_t a : cells) verts.insert(verts.end(), c.verts.begin() + c.offsets[a], c.verts.begin() + c.offsets[a + 1]);
}

std::vector<int32_t> cluster_order(const CellGraph& c, std::span<const int32_t> seed_order, int batch) {
  const int32_t ns = static_cast<int32_t>(seed_order.size());
  std::vector<int32_t> out, queue;
  out.reserve(ns);
  std::vector<uint8_t> taken(ns, 0), queued(ns, 0);
  size_t next = 0;
  while (static_cast<int32_t>(out.size()) < ns) {
    const size_t batch_start = out.size();
    queue.clear();
    size_t head = 0;
    while (out.size() - batch_start < static_cast<size_t>(batch) && static_cast<int32_t>(out.size()) < ns) {
      if (head == queue.size()) {  // patch exhausted: the next untaken cell in seed order
        while (taken[seed_order[next]]) ++next;
        queue.push_back(seed_order[next]);
        queued[seed_order[next]] = 1;
      }
      const int32_t s = queue[head++];
      taken[s] = 1;
      out.push_back(s);
      for (int64_t p = c.adj_offsets[s]; p < c.adj_offsets[s + 1]; ++p) {
        const int32_t a = c.adj[p];
        if (!taken[a] && !queued[a]) {
          queued[a] = 1;
          queue.push_back(a);
        }
      }
    }
    for (int32_t q : queue) queued[q] = 0;
  }
  return out;
}

}  // namespace locus
