// Vertex-separator refinement by Fiduccia-Mattheyses passes (issue 26;
// thesis §4.2: the separators of a nested dissection decide its fill). The
// cheap separators of the deep levels (level_separator.hpp, the geometric
// cut) are rough; a few FM passes shorten them to within a few percent of
// METIS' multilevel ones at a fraction of the cost, because a rough
// separator of a mesh graph is mostly a jagged wavefront that local moves
// straighten.
//
// One pass moves separator vertices into one side `to`; the neighbors of a
// moved vertex on the other side enter the separator. The gain of a move is
// its weight - (the weight of its neighbors on the other side). Moves are taken best gain first
// (ties: lowest vertex), negative gains included (hill climbing), and the
// pass is rolled back to its smallest balanced separator. Passes alternate
// the side. Deterministic: no random numbers, ties by vertex index.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"

namespace locus {

struct SeparatorRefinementOptions {
  int passes = 8;             // at most this many passes (stops after two without improvement)
  double max_imbalance = 1.2;  // each side at most this times half the vertices outside the separator
  bool balance_with_separator = false;  // ... half of all vertices, separator included
  int32_t patience_factor = 2;          // a pass goes on for this times the separator's vertices past its best
  int32_t patience_cap = 300;           // ... but at most this many moves
  int32_t stretch = 1;                  // or this times as many while within 10% of its best
};

// part[v] = 0, 1 (sides) or 2 (separator), no edge between sides 0 and 1 (on
// entry and on return). vwgt: one weight per vertex (a coarse vertex of the
// nested dissection's hierarchy weighs the fine vertices it stands for);
// empty, every vertex weighs 1. Gains, balance and the returned separator
// size are weights.
int32_t refine_vertex_separator(const AdjacencyGraph& g, HostVector<int8_t>& part,
                                const SeparatorRefinementOptions& opt = {}, std::span<const int32_t> vwgt = {});

}  // namespace locus
