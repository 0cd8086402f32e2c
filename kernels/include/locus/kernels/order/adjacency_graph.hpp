// The graph an ordering works on (thesis §4.2): the off-diagonal
// pattern of a symmetric matrix as a symmetric adjacency in CSR, 32-bit
// indices (what METIS and AMD take), neighbors ascending, no self loops.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct AdjacencyGraph {
  HostVector<int32_t> xadj{0};  // n + 1
  HostVector<int32_t> adj;      // xadj[n], both directions of every edge
  int32_t n() const { return static_cast<int32_t>(xadj.size()) - 1; }
  int32_t degree(int32_t v) const { return xadj[v + 1] - xadj[v]; }
};

// Both triangles of a lower-stored symmetric matrix, diagonal dropped. O(nnz).
// Throws ResourceLimit when the graph has 2^31 or more directed edges.
AdjacencyGraph adjacency_of(const CscMatrix& lower);

// The subgraph induced by the vertices v with part[v] == which, numbered in
// ascending order of v; global receives the original index of each vertex.
AdjacencyGraph induced_subgraph(const AdjacencyGraph& g, std::span<const int8_t> part, int8_t which,
                                HostVector<int32_t>& global);

}  // namespace locus
