// Nested dissection as a oneTBB task tree (thesis §4.2): a vertex
// separator splits the graph, the two sides are ordered as independent tasks,
// the separator is numbered after both; below `leaf_size` vertices a side is
// ordered by AMD (kernels/include/locus/kernels/order/minimum_degree.hpp).
// The separators come from the vertex positions when the caller has them
// (geometric_separator.hpp) or from METIS (METIS_ComputeVertexSeparator):
// by default METIS separates each large node's contraction along one
// coarsening of the whole graph made before the tree (graph_coarsening.hpp),
// and FM passes refine the projected separator on the node's own vertices
// (separator_refinement.hpp): METIS no longer coarsens every node from
// scratch (0.55x the ordering's CPU at 416k, within 1% of its fill,
// docs/ordering.md). Nodes below exact_min_vertices take their contraction
// from their parent's instead of contracting their own graph; the smallest
// contractions are cut by a level structure (level_separator.hpp), and the
// largest nodes keep the best of several separators (separator_tries).
//
// Deterministic: every task's result depends on its subgraph only, and its
// place in the ordering on the sizes of the subgraphs before it, never on
// which thread ran it or when; 1, 2 or 16 threads give the same permutation.
// Cancellation: the flag in ctx is polled at every node of the tree and at
// every allocation inside METIS (metis_call.hpp), so a raised flag throws
// Error(Cancelled) within milliseconds. Progress "ordering": the fraction of
// vertices placed, reported at most every 20 ms (progress_ticker.hpp).
#pragma once
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"
#include "locus/kernels/order/geometric_separator.hpp"
#include "locus/kernels/order/metis_ordering.hpp"
#include "locus/kernels/order/separator_refinement.hpp"
#include "locus/run_context.hpp"

namespace locus {

struct NestedDissectionOptions {
  enum class Separator { Geometric, Metis } separator = Separator::Geometric;
  int32_t leaf_size = 256;  // subgraphs of at most this many vertices are ordered by AMD
  bool halo = true;         // leaves by CAMD with their separator halo (else AMD alone)
  GeometricSeparatorOptions geometric;
  int metis_seed = 7;
  // Shared coarsening (graph_coarsening.hpp): nodes of at least
  // coarse_min_vertices take METIS' separator of their contraction by
  // coarse_levels rounds of matching, refined on their own vertices (0: off).
  int coarse_levels = 0;
  int32_t coarse_min_vertices = 5000;
  // METIS sees how many edges join two coarse vertices (its heavy-edge
  // matching of the contraction is blind without them).
  bool metis_edge_weights = true;
  // Nodes of at least this many vertices contract their own graph; smaller
  // ones cut their contraction out of their parent's (restrict_contraction:
  // a pass over the small graph instead of the node's). Default: only the
  // root contracts (with 5 coarse levels contracting the large nodes again
  // gains no fill and costs 10% of the ordering at 416k, docs/ordering.md).
  int32_t exact_min_vertices = std::numeric_limits<int32_t>::max();
  // Contractions of fewer vertices than this are separated by a level
  // structure (level_separator.hpp) instead of METIS (0: METIS always):
  // at 416k ~2000 of the ~2100 METIS calls were on contractions this small,
  // 0.08 s of CPU; the FM passes that follow make up for the cruder cut
  // (fill +0.4%, docs/ordering.md).
  int32_t level_separator_below = 100;
  // Large nodes keep the smallest of several separators (METIS seeds
  // metis_seed + k, each refined), tried in parallel: separator_tries at
  // nodes of tries_full_vertices or more, half as many for every halving of
  // the node below that, at least one (at 416k: 4 at the root, 2 at its
  // children, then one). The top separators lie on every local solve's
  // path: at 416k one try gave the 24-lane solve +8% against METIS_NodeND.
  // Twice as many (8 at the 416k root, 4, 2) cost 0.07 s more CPU there for
  // the same ordering, and on four other inputs gave no better fill or
  // etree overall (docs/ordering.md).
  int separator_tries = 8;
  int32_t tries_full_vertices = 800000;
  SeparatorRefinementOptions refinement;
};

// perm[k] = vertex eliminated k-th. x, y, z: vertex positions (one per vertex
// of g, finite), needed by the geometric separator only. Runs with ctx.threads.
HostVector<int32_t> nested_dissection(const AdjacencyGraph& g, std::span<const double> x, std::span<const double> y,
                                       std::span<const double> z, const NestedDissectionOptions& opt,
                                       const RunContext& ctx);

}  // namespace locus
