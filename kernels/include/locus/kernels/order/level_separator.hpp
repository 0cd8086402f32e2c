// Level-structure vertex separators of small graphs (thesis §4.2):
// the nested dissection's nodes of a few hundred to a few thousand vertices
// have contractions of under ~200 vertices, where a METIS call costs
// 30-60 us, mostly its fixed setup and repeated initial bisections
// (docs/ordering.md). A breadth-first level structure from a
// pseudo-peripheral vertex gives a separator in a few passes over the small
// graph; the FM passes on the node's own vertices refine it afterwards, as
// they refine METIS' projected separators.
#pragma once
#include <cstdint>
#include <span>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"

namespace locus {

// part[v] = 0 or 1 (sides) or 2 (separator), no edge between sides 0 and 1:
// the separator is one level of the breadth-first search from a
// pseudo-peripheral vertex, the level that balances the weights vwgt (one
// per vertex) best, lighter levels preferred among balanced ones. Returns
// false (part untouched) when g is not connected or has fewer than 3 levels;
// the caller then asks METIS. Deterministic.
bool level_separator(const AdjacencyGraph& g, std::span<const int32_t> vwgt, HostVector<int8_t>& part);

}  // namespace locus
