// METIS behind the orderings: its vertex separator for the nested
// dissection task tree, and METIS_NodeND as it ran before the task tree (the
// Method::Metis ordering, kept as the reference the new orderings are
// measured against, docs/ordering.md). Every call draws its random numbers
// from a generator of its own (metis_random.hpp), so concurrent calls are
// reproducible.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"
#include "locus/run_context.hpp"

namespace locus {

// part[v] = 0 or 1 (sides) or 2 (separator), by METIS_ComputeVertexSeparator
// (vertex weights vwgt when given, one per vertex: balance by weight; edge
// weights adjwgt when given, one per entry of g.adj, symmetric: they guide
// METIS' heavy-edge matching). With a ticker, METIS' allocations tick its
// progress and stop the call once the ticker's cancel flag is up
// (Error(Cancelled); metis_call.hpp).
void metis_vertex_separator(const AdjacencyGraph& g, int seed, HostVector<int8_t>& part,
                            ProgressTicker* ticker = nullptr, std::span<const int32_t> vwgt = {},
                            std::span<const int32_t> adjwgt = {});

// METIS_NodeND; graphs of 4000 vertices or more split once by a METIS
// separator, the two halves ordered at once on two oneTBB threads of the
// caller's arena when ctx.threads allows. The cancel flag is polled at every
// allocation inside METIS (metis_call.hpp), progress reported as "ordering".
HostVector<int32_t> metis_nested_dissection(const AdjacencyGraph& g, int seed, const RunContext& ctx);

}  // namespace locus
