// METIS separators and METIS_NodeND (kernels/include/locus/kernels/order/metis_ordering.hpp).
//
// METIS runs with a fixed seed so the ordering, and with it every factor and
// every result downstream, is reproducible. Graph compression is off: mesh
// graphs have no vertices with identical neighborhoods, so METIS' detection
// pass only costs time. metis_nested_dissection splits once: METIS finds the
// top separator, and the two halves are ordered by METIS_NodeND at the same
// time on two oneTBB threads; the split depends on the graph only, never on
// the thread count, so one thread gives the same ordering.
#include "locus/kernels/order/metis_ordering.hpp"

#include <metis.h>

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <numeric>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/order/metis_call.hpp"
#include "locus/kernels/order/metis_random.hpp"

// kernels/src/order/metis_trap.c: METIS_ComputeVertexSeparator inside GKlib's error trap.
extern "C" int locus_metis_vertex_separator(idx_t* nvtxs, idx_t* xadj, idx_t* adjncy, idx_t* vwgt, idx_t* adjwgt,
                                            idx_t* options, idx_t* sepsize, idx_t* part);

namespace locus {

namespace {

static_assert(sizeof(idx_t) == sizeof(int32_t), "METIS is compiled with 32-bit indices");

// Below this size one METIS_NodeND call is cheaper than a split and a thread.
constexpr int32_t kSplitMinVertices = 4000;

void set_options(idx_t* options, int seed) {
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_SEED] = seed;
  options[METIS_OPTION_COMPRESS] = 0;
}

void check_status(int rc, int32_t n, const char* what, const MetisCallScope& scope) {
  if (rc == METIS_OK) return;
  if (scope.stopped()) fail(ErrorCode::Cancelled, "cancelled");
  if (rc == METIS_ERROR_MEMORY)
    fail(ErrorCode::ResourceLimit, std::string("out of memory in ") + what + " (a graph of " + std::to_string(n) +
                                       " vertices)");
  fail(rc == METIS_ERROR_MEMORY ? ErrorCode::ResourceLimit : ErrorCode::Internal,
       std::string(what) + " failed with status " + std::to_string(rc) + " on a graph of " + std::to_string(n) +
           " vertices");
}

// METIS takes non-const arrays (it does not write them for these calls).
idx_t* mut(const HostVector<int32_t>& v) { return const_cast<idx_t*>(v.data()); }

// Nested dissection of g into perm (perm[k] = vertex of g eliminated k-th).
void node_nd(const AdjacencyGraph& g, int seed, int32_t* perm, ProgressTicker* ticker) {
  idx_t nv = g.n();
  if (nv == 0) return;
  if (g.adj.empty()) {  // no edges: any order has no fill (and METIS rejects it)
    std::iota(perm, perm + nv, 0);
    return;
  }
  idx_t options[METIS_NOPTIONS];
  set_options(options, seed);
  HostVector<idx_t> iperm(static_cast<size_t>(nv));
  MetisRandomScope rng;
  MetisCallScope call(ticker);
  check_status(METIS_NodeND(&nv, mut(g.xadj), mut(g.adj), nullptr, options, perm, iperm.data()), g.n(),
               "METIS_NodeND", call);
}

}  // namespace

void metis_vertex_separator(const AdjacencyGraph& g, int seed, HostVector<int8_t>& part, ProgressTicker* ticker,
                            std::span<const int32_t> vwgt, std::span<const int32_t> adjwgt) {
  idx_t nv = g.n();
  part.assign(nv, 0);
  if (nv < 2 || g.adj.empty()) return;  // nothing to separate (METIS rejects edgeless graphs)
  idx_t options[METIS_NOPTIONS];
  set_options(options, seed);
  HostVector<idx_t> where(static_cast<size_t>(nv));
  idx_t sepsize = 0;
  {
    MetisRandomScope rng;
    MetisCallScope call(ticker);
    idx_t* w = vwgt.empty() ? nullptr : const_cast<idx_t*>(vwgt.data());
    idx_t* ew = adjwgt.empty() ? nullptr : const_cast<idx_t*>(adjwgt.data());
    check_status(locus_metis_vertex_separator(&nv, mut(g.xadj), mut(g.adj), w, ew, options, &sepsize, where.data()),
                 g.n(), "METIS_ComputeVertexSeparator", call);
  }
  for (idx_t v = 0; v < nv; ++v) part[v] = static_cast<int8_t>(where[v]);
}

HostVector<int32_t> metis_nested_dissection(const AdjacencyGraph& g, int seed, const RunContext& ctx) {
  const int32_t n = g.n();
  HostVector<int32_t> order(static_cast<size_t>(n));
  ctx.check_cancel();
  // METIS reports no progress of its own: the ticker re-reports the last
  // fraction from its allocations (chances to cancel) and advances by halves.
  ProgressTicker ticker(ctx, "ordering", 4.0);
  if (n < kSplitMinVertices) {
    node_nd(g, seed, order.data(), &ticker);
    return order;
  }
  HostVector<int8_t> part;
  metis_vertex_separator(g, seed, part, &ticker);
  ticker.add(1.0);
  ctx.check_cancel();
  HostVector<int32_t> global0, global1;
  const AdjacencyGraph h0 = induced_subgraph(g, part, 0, global0);
  const AdjacencyGraph h1 = induced_subgraph(g, part, 1, global1);
  HostVector<int32_t> p0(global0.size()), p1(global1.size());
  const bool two_threads = ctx.threads != 1 && (ctx.threads > 1 || tbb::this_task_arena::max_concurrency() > 1);
  if (two_threads && !global0.empty() && !global1.empty()) {
    // oneTBB threads of the caller's arena; one METIS call never waits on
    // oneTBB, so a thread cannot start the other half inside this one's scope.
    tbb::parallel_invoke([&] { node_nd(h0, seed, p0.data(), &ticker); ticker.add(1.5); },
                         [&] { node_nd(h1, seed, p1.data(), &ticker); ticker.add(1.5); });
  } else {
    node_nd(h0, seed, p0.data(), &ticker);
    ticker.add(1.5);
    ctx.check_cancel();
    node_nd(h1, seed, p1.data(), &ticker);
    ticker.add(1.5);
  }
  size_t k = 0;
  for (const int32_t v : p0) order[k++] = global0[v];
  for (const int32_t v : p1) order[k++] = global1[v];
  for (int32_t v = 0; v < n; ++v)
    if (part[v] == 2) order[k++] = v;
  return order;
}

}  // namespace locus
