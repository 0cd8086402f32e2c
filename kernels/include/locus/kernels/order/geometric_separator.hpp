// Vertex separators from vertex positions (thesis §4.2): the mesh's
// geometry tells roughly where a short cut lies, so a plane cut plus a small
// combinatorial repair can stand in for METIS' multilevel search. The cut
// alone is jagged (1.5-1.8x METIS' separators on armadillo, 1.1-1.25x the
// fill); the nested dissection refines it by FM passes
// (separator_refinement.hpp), after which the fill is METIS_NodeND's (0.97x
// at 26k, 1.00x at 104k, 1.03x at 416k on armadillo). It is an option, not
// the default: at 416k its etree is 1.17x METIS_NodeND's and it costs more
// than the shared-coarsening separators (docs/ordering.md).
//
// The cut: for each principal axis of the points' inertia (and the diagonals
// between them), the split point along it is chosen among bin boundaries
// inside a window around the median to cut the fewest edges; the direction
// with the fewest cut edges wins. The separator: a minimum vertex cover of
// the cut edges (König: a maximum matching of the bipartite cut graph), so no
// vertex is in the separator that a smaller cover could leave out.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"

namespace locus {

struct GeometricSeparatorOptions {
  double balance_window = 0.15;  // split point within (0.5 -+ this) of the vertices
  bool diagonals = true;         // also try the 4 diagonals between the principal axes
};

// part[v] = 0 or 1 (the two sides), or 2 (separator); no edge joins side 0 to
// side 1. x, y, z: one position per vertex of g (finite). Deterministic.
void geometric_separator(const AdjacencyGraph& g, std::span<const double> x, std::span<const double> y,
                         std::span<const double> z, const GeometricSeparatorOptions& opt, HostVector<int8_t>& part);

// From a bisection (part[v] = 0 or 1), moves a minimum vertex cover of the
// edges between the sides into the separator (part[v] = 2).
void minimum_cover_separator(const AdjacencyGraph& g, HostVector<int8_t>& part);

}  // namespace locus
