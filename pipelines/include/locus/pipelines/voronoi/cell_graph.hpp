// The cells of a vertex labelling and their adjacency graph, and the batches of
// neighboring cells that Lloyd's method solves together (thesis §3.6-3.7.1: a
// batch of 8 cells shares one 8-lane localized solve, restricted to the batch's
// cells and their two rings of neighbor cells).
//
// Cells are CSR lists of their vertices (ascending); two cells are adjacent when
// an edge joins them. A batch is grown breadth-first over the cell graph from
// the first cell not yet taken in a given seed order (the Morton order of the
// sites), so the union of a batch's two-ring neighborhoods (its kept set) is close
// to the two rings around one compact patch of cells rather than around scattered
// ones.
//
// Deterministic: sorted adjacency lists, fixed seed order. build_cell_graph runs
// its per-cell sorts in parallel in the caller's arena; the rest is sequential.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"

namespace locus {

struct CellGraph {
  HostVector<int64_t> offsets;      // cells + 1: CSR of the cells' vertices
  HostVector<int32_t> verts;        //   ascending within a cell
  HostVector<int64_t> adj_offsets;  // cells + 1: CSR of the neighbor cells
  HostVector<int32_t> adj;          //   ascending, without repeats
};

// label[v] in [0, cells) for every vertex v (the caller checks); `edges` the mesh's
// unique edges.
CellGraph build_cell_graph(const Edges& edges, std::span<const int32_t> label, int32_t cells);
// The same graph from the vertex adjacency (each edge from its smaller end), for
// callers that hold the adjacency and not the edges (Lloyd's iterations).
CellGraph build_cell_graph(const Adjacency& adj, std::span<const int32_t> label, int32_t cells);

// Cell s, its neighbor cells and their neighbors, appended to `out` (with repeats).
void append_two_ring_cells(const CellGraph& g, int32_t s, std::vector<int32_t>& out);

// The vertices of a list of cells: `cells` is sorted and deduplicated in place,
// `verts` becomes the concatenation of their vertex lists (unique: cells are
// disjoint; ascending within each cell only).
void cells_to_vertices(const CellGraph& g, std::vector<int32_t>& cells, HostVector<int32_t>& verts);
// The same appended to `verts` (kept as it was).
void append_cells_vertices(const CellGraph& g, std::vector<int32_t>& cells, HostVector<int32_t>& verts);

// Every cell once, in runs of `batch` neighboring cells (the last run may be
// shorter): each run breadth-first over the graph (neighbors in ascending id),
// restarted from the first untaken cell of `seed_order` (a permutation of the
// cells) when its patch is exhausted.
std::vector<int32_t> cluster_order(const CellGraph& g, std::span<const int32_t> seed_order, int batch);

}  // namespace locus
