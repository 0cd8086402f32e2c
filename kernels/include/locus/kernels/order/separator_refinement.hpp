// Vertex-separator refinement by Fiduccia-Mattheyses passes (thesis
// §4.2: the separators of a nested dissection decide its fill). The
// cheap separators of the deep levels (level_separator.hpp, the geometric
// cut) are rough; a few FM passes shorten them to within a few percent of
// METIS' multilevel ones at a fraction of the cost, because a rough
// separator of a mesh graph is mostly a jagged wavefront that local moves
// straighten.
//
// One pass moves separator vertices into one side `to`; the neighbors of a
// moved vertex on the other side enter the separator. The gain of a move is
// 1 - (its neighbors on the other side). Moves are taken best gain first
// (ties: the vertex whose gain was set last), negative gains included (hill
// climbing, kept up longer while the separator stays within 10% of the
// pass' best), and the pass is rolled back to its smallest balanced
// separator. Passes alternate the side. Deterministic: no random numbers.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"

namespace locus {

struct SeparatorRefinementOptions {
  int passes = 8;             // at most this many passes (stops after two without improvement)
  // Each side at most this times half the vertices outside the separator.
  // 1.3 rather than METIS' 1.2: 0.5-1% less fill at 416k, the etree no
  // higher (docs/ordering.md).
  double max_imbalance = 1.3;
  int32_t patience = 300;  // a pass goes on 2x the separator's size past its best state, at most this many moves
  int32_t stretch = 3;     // ... or this times as long while the separator stays within 10% of the best
};

// Arrays of one thread's refinements, kept from call to call: per-vertex
// marks sized for the largest graph so far, which a call only reads where it
// wrote them, so a call costs nothing for the vertices it never touches (a
// fresh set costs 16 bytes and a page fault share per vertex of the graph,
// 1-2 ms at 416k, at every node of a dissection). Not for two calls at once.
struct SeparatorRefinementWorkspace {
  HostVector<int32_t> gain;
  HostVector<int64_t> stamp, joined;
  int64_t next_pass = 0, move_id = 0;
  std::vector<HostVector<int32_t>> buckets;
  HostVector<int32_t> sep, moved, pulled, pulled_begin;
};

// part[v] = 0, 1 (sides) or 2 (separator), no edge between sides 0 and 1 (on
// entry and on return). Returns the separator size. `ws`: a workspace to
// reuse (none: one for this call).
int32_t refine_vertex_separator(const AdjacencyGraph& g, HostVector<int8_t>& part,
                                const SeparatorRefinementOptions& opt = {},
                                SeparatorRefinementWorkspace* ws = nullptr);

}  // namespace locus
