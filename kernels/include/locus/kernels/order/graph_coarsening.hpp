// One coarsening of the whole graph, shared by every level of the nested
// dissection (issue 26; thesis §4.2). METIS coarsens each subgraph it
// separates from scratch, so a dissection with ~11 levels coarsens the whole
// graph ~11 times; that was most of the ordering's time (docs/ordering.md).
// Here the graph is matched once (heavy-edge matching, a few levels); each
// node of the dissection contracts its own subgraph along that map in one
// pass, asks METIS for a separator of the small weighted graph, and refines
// the projected separator on its own vertices (separator_refinement.hpp).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"

namespace locus {

// The levels of a multilevel coarsening: maps[l][v] = vertex of level l + 1
// that vertex v of level l belongs to (level 0: the graph itself); sizes[l] =
// vertices of level l (levels() + 1 entries). Rounds that match nothing
// (no edges left) end it early.
struct CoarseningHierarchy {
  std::vector<HostVector<int32_t>> maps;
  std::vector<int32_t> sizes;
  int levels() const { return static_cast<int>(maps.size()); }
};

// `levels` rounds of heavy-edge matching as described under coarsening_map,
// each round's map kept (the nested dissection refines its separators at
// every level on the way back, as a multilevel bisection does).
CoarseningHierarchy coarsening_hierarchy(const AdjacencyGraph& g, int levels, ProgressTicker* ticker = nullptr);

// cmap[v] = coarse vertex of v after `levels` rounds of matching (each coarse
// vertex stands for at most 2^levels vertices); returns the number of coarse
// vertices. Each round visits the vertices in a fixed pseudo-random order and
// pairs each unmatched one with the unmatched neighbor joined by the most
// edges of the original graph (ties: fewest neighbors, then lowest index).
// Deterministic.
// `ticker`, when given, reports and polls the cancel flag between the passes.
int32_t coarsening_map(const AdjacencyGraph& g, int levels, HostVector<int32_t>& cmap, ProgressTicker* ticker = nullptr);

// The graph of g contracted along coarse[v] in [0, nc): coarse vertices
// joined when any of their vertices are; vwgt[c] = summed fine_vwgt of c's
// vertices (fine_vwgt empty: each weighs 1). With ewgt, (*ewgt)[p] = summed
// fine_ewgt (one per entry of g.adj; empty: 1) of the fine edges behind
// coarse edge h.adj[p]. Self loops dropped; neighbor lists in order of first
// appearance (METIS needs no order).
AdjacencyGraph contract_graph(const AdjacencyGraph& g, std::span<const int32_t> coarse, int32_t nc,
                              HostVector<int32_t>& vwgt, std::span<const int32_t> fine_vwgt = {},
                              HostVector<int32_t>* ewgt = nullptr, std::span<const int32_t> fine_ewgt = {});

}  // namespace locus
