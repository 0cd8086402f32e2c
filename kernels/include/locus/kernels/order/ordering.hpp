// Fill-reducing orderings of the graph of a symmetric matrix (thesis §4.2: the
// etree height an ordering produces decides the cost of local solves; and
// the ordering is most of the time to a first answer on a new mesh).
//
// Methods: nested dissection as a oneTBB task tree with AMD leaves
// (nested_dissection.hpp), its separators from the vertex positions when the
// caller passes them, else from METIS on a shared coarsening refined by FM
// passes; AMD alone; METIS_NodeND as it ran
// before the task tree (the reference of docs/ordering.md); natural order.
// Auto (the default) picks by size, from the measurements in docs/ordering.md.
// Deterministic: the same input gives the same ordering for any thread count.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct Ordering {
  HostVector<int32_t> perm;   // perm[k]  = original index eliminated k-th
  HostVector<int32_t> iperm;  // iperm[i] = position of original index i
};

struct OrderingOptions {
  enum class Method {
    Auto,              // Metis below amd_min_vertices, Amd up to amd_max_vertices, NestedDissection above
    NestedDissection,  // task tree with (C)AMD leaves, separators as chosen below
    Amd,               // approximate minimum degree of the whole graph
    Metis,             // METIS_NodeND, one top split on two threads (the pre-task-tree ordering)
    Natural            // identity
  } method = Method::Auto;
  // NestedDissection's separators: METIS' on the shared coarsening, or plane
  // cuts from the vertex positions below refined by FM passes (Geometric: the
  // same fill up to 104k on armadillo, 1.03x and a 1.17x taller etree at
  // 416k, 1.1-1.2x the CPU, docs/ordering.md; without usable positions METIS
  // is used).
  enum class Separator { Metis, Geometric } separator = Separator::Metis;
  int seed = 7;  // METIS random seed (fixed: same input, same ordering)
  // Vertex positions, one per matrix column (a mesh's x, y, z when the matrix
  // is a vertex operator), for Separator::Geometric. Non-finite positions are
  // ignored (as if none were given).
  std::span<const double> x, y, z;
  // Auto: AMD up to this size. Below it AMD's fill is within ~1.2x of nested
  // dissection's at a fraction of the time, so the first answer comes sooner;
  // above it nested dissection's shorter etrees and lower fill pay for it
  // (local solves, numeric time). Measurements: docs/ordering.md.
  int32_t amd_max_vertices = 120000;
  // Auto: below this size the ordering costs milliseconds whatever the
  // method, so the one with the shorter etree (METIS_NodeND) is kept: small
  // systems factor exactly as with the reference ordering (Method::Metis).
  int32_t amd_min_vertices = 4000;
  // NestedDissection with METIS separators: the graph is coarsened once by
  // coarse_levels rounds of heavy-edge matching (graph_coarsening.hpp); a
  // node of at least coarse_min_vertices takes METIS' separator of its
  // contraction (~26x smaller at 5 levels), refined on its own vertices by
  // FM passes. 5 levels: 0.7x the ordering's CPU of 3 at 416k for the same
  // fill within 1% (docs/ordering.md); coarse_levels = 0 calls METIS on
  // every node's full graph. 256: every node above the default leaf size
  // (METIS on the small nodes' own graphs was a quarter of the ordering's
  // CPU, for no less fill).
  int coarse_levels = 5;
  int32_t coarse_min_vertices = 256;
  int32_t leaf_size = 256;  // NestedDissection: leaves of at most this many vertices by (C)AMD
  bool halo = true;         // NestedDissection: leaves ordered with their separator halo (CAMD)
};

// Orders the graph of a lower-stored symmetric matrix with ctx.threads threads.
// The cancel flag in ctx is polled between the tasks of the ordering and
// inside METIS' calls (metis_call.hpp; AMD alone, Method::Amd or Auto up to
// amd_max_vertices, cannot be interrupted) and raises Error(Cancelled);
// nothing is left running. Progress: phase "ordering".
// Throws BadUsage if the matrix is not square or positions have the wrong size.
Ordering order_matrix(const CscMatrix& lower, const OrderingOptions& opt = {}, const RunContext& ctx = {});

}  // namespace locus
