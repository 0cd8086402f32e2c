// Approximate minimum degree ordering (AMD; Amestoy, Davis & Duff 1996) of a
// graph, through SuiteSparse's AMD and CAMD (Debian libamd/libcamd,
// BSD-3-clause).
// Small graphs, and the leaves of the nested dissection, are ordered by it:
// below a few thousand vertices it is faster than any separator and its fill
// is as low as nested dissection's.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"

namespace locus {

// perm[k] = vertex eliminated k-th. Deterministic (AMD uses no random numbers).
// Throws ResourceLimit when AMD cannot allocate its workspace.
HostVector<int32_t> minimum_degree_order(const AdjacencyGraph& g);

// CAMD (constrained AMD, same license): vertices with constraint 0 first, then
// those with constraint 1, each set in minimum degree order. The nested
// dissection orders a leaf with its halo (the separator vertices around it)
// as constraint-1 vertices: the leaf's order then accounts for the fill its
// boundary will take (Pellegrini's halo ordering). Returns the whole order.
// g as every AdjacencyGraph: symmetric, no self loops, no repeated neighbor;
// with ascending lists the order is exactly camd_order's. Constraint values
// lie in [0, n) (else BadUsage).
HostVector<int32_t> constrained_minimum_degree_order(const AdjacencyGraph& g, const HostVector<int32_t>& constraint);

}  // namespace locus
