// Vertex separators from breadth-first level structures (issue 26; thesis
// §4.2), for the deep levels of the nested dissection where METIS' multilevel
// bisection costs more than the quality it adds there (docs/ordering.md).
//
// The levels of a breadth-first search from a pseudo-peripheral vertex (the
// far end of repeated searches) are vertex separators of the graph: edges
// join only consecutive levels. Among the levels that split the vertices
// within the balance window the smallest is taken, then shortened by FM
// passes (separator_refinement.hpp). Works on any graph, no positions needed.
// Disconnected graphs: whole components go to the sides when they balance,
// else the largest component is cut and the others join its lighter side.
// Deterministic (searches start from the lowest-numbered vertex).
#pragma once
#include <cstdint>
#include <vector>

#include "locus/kernels/order/adjacency_graph.hpp"
#include "locus/kernels/order/separator_refinement.hpp"

namespace locus {

struct LevelSeparatorOptions {
  double balance_window = 0.1;  // the cut level within (0.5 -+ this) of the vertices
  int sweeps = 3;               // searches to find a pseudo-peripheral start vertex
  SeparatorRefinementOptions refinement;
};

// part[v] = 0 or 1 (the two sides), or 2 (separator); no edge joins side 0 to side 1.
void level_separator(const AdjacencyGraph& g, const LevelSeparatorOptions& opt, std::vector<int8_t>& part);

}  // namespace locus
