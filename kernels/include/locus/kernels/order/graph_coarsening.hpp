// One coarsening of the whole graph, shared by every level of the nested
// dissection (thesis §4.2). METIS coarsens each subgraph it
// separates from scratch, so a dissection with ~11 levels coarsens the whole
// graph ~11 times; that was most of the ordering's time (docs/ordering.md).
// Here the graph is matched once (heavy-edge matching, a few levels); each
// node of the dissection contracts its own subgraph along that map in one
// pass (or cuts it out of its parent's contraction), asks METIS for a
// separator of the small weighted graph, and refines the projected separator
// on its own vertices (separator_refinement.hpp).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"

namespace locus {

// cmap[v] = coarse vertex of v after `levels` rounds of matching (each coarse
// vertex stands for at most 2^levels vertices); returns the number of coarse
// vertices. Each round is a maximal heavy-edge matching of the current
// graph: edges ranked by the number of edges of the original graph they
// stand for, then by the fewest neighbors of the two ends, then by a hash
// of the pair (pseudo-random, fixed); every unmatched vertex points at its
// best-ranked unmatched neighbor and mutual pointers match, in synchronous
// rounds (about the greedy matching in rank order). Coarse vertices are
// numbered in the order of their lowest vertex. Parallel (oneTBB, the
// caller's arena) and the same map for any thread count.
// `ticker`, when given, reports and polls the cancel flag between the passes.
// With `coarsest`, also the graph of the last level (what contract_graph
// would give, up to the order in the neighbor lists), from the level above
// it: a pass over that level's rows instead of over g's.
struct Contraction {
  AdjacencyGraph graph;
  HostVector<int32_t> ewgt;  // edges of g behind each entry of graph.adj
};
int32_t coarsening_map(const AdjacencyGraph& g, int levels, HostVector<int32_t>& cmap, ProgressTicker* ticker = nullptr,
                       Contraction* coarsest = nullptr);

// The graph of g contracted along coarse[v] in [0, nc): coarse vertices
// joined when any of their vertices are; vwgt[c] = vertices of c; with
// ewgt, (*ewgt)[p] = the edges of g behind coarse edge h.adj[p] (what a
// heavy-edge matching of h needs). Self loops dropped; neighbor lists in
// order of first appearance (METIS needs no order). Rows are built in fixed
// blocks in parallel (oneTBB, the caller's arena): the same graph for any
// thread count.
AdjacencyGraph contract_graph(const AdjacencyGraph& g, std::span<const int32_t> coarse, int32_t nc,
                              HostVector<int32_t>& vwgt, HostVector<int32_t>* ewgt = nullptr);

// The contraction of a subgraph, cut out of the contraction h of the whole
// graph (one pass over h instead of one over the subgraph): keep[c] = index
// of coarse vertex c in the result (it has a vertex in the subgraph), or -1;
// nkept of them. The edges of h between kept vertices stay, with their
// weights ewgt (one per entry of h.adj; empty: none) in *kept_ewgt. That is
// the subgraph's exact contraction, except that a coarse vertex that lost
// vertices keeps the edges it had through them: extra edges only, so a
// vertex separator of the result separates the exact contraction too.
AdjacencyGraph restrict_contraction(const AdjacencyGraph& h, std::span<const int32_t> keep, int32_t nkept,
                                    std::span<const int32_t> ewgt = {}, HostVector<int32_t>* kept_ewgt = nullptr);

}  // namespace locus
