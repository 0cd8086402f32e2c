// Fill-reducing ordering by METIS nested dissection (kernels/include/locus/kernels/order/ordering.hpp).
//
// The graph is the off-diagonal pattern of the symmetric matrix, built in
// O(nnz) by counting. METIS runs with a fixed seed so the ordering, and with
// it every factor and every result downstream, is reproducible.
//
// Large graphs are dissected once here: METIS finds the top separator, and
// the two halves are ordered by METIS_NodeND at the same time on two oneTBB
// threads (each half's random numbers come from its own generator, see
// kernels/include/locus/kernels/order/metis_random.hpp). The split depends on the graph only, never on the
// thread count, so one thread gives the same ordering, one half after the
// other. Graph compression is off: mesh graphs have no vertices with identical
// neighborhoods, so METIS' detection pass only costs time.
#include "locus/kernels/order/ordering.hpp"

#include <metis.h>

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <numeric>
#include <string>

#include "locus/kernels/order/metis_random.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

// Full symmetric adjacency (both triangles, no diagonal) of a lower-stored matrix.
void matrix_graph(const CscMatrix& A, std::vector<idx_t>& xadj, std::vector<idx_t>& adjncy) {
  const int32_t n = A.ncols;
  std::vector<idx_t> deg(static_cast<size_t>(n) + 1, 0);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i != j) { ++deg[i]; ++deg[j]; }
    }
  xadj.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t j = 0; j < n; ++j) xadj[j + 1] = xadj[j] + deg[j];
  adjncy.resize(static_cast<size_t>(xadj[n]));
  std::vector<idx_t> pos(xadj.begin(), xadj.end() - 1);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i != j) { adjncy[pos[i]++] = j; adjncy[pos[j]++] = i; }
    }
}

// Below this size one METIS_NodeND call is cheaper than a split and a thread.
constexpr idx_t kSplitMinVertices = 4000;

struct Graph {
  std::vector<idx_t> xadj, adjncy;
  idx_t n() const { return static_cast<idx_t>(xadj.size()) - 1; }
};

void check_cancel_during_metis(const RunContext& ctx) {
  if (ctx.cancelled()) fail(ErrorCode::Cancelled, "cancelled (during the METIS ordering)");
}

// Nested dissection of g into perm (perm[k] = vertex of g eliminated k-th).
int node_nd(Graph& g, const idx_t* base_options, idx_t* perm) {
  idx_t nv = g.n();
  if (nv == 0) return METIS_OK;
  if (g.xadj[nv] == 0) {  // no edges: any order has no fill (and METIS rejects it)
    std::iota(perm, perm + nv, idx_t{0});
    return METIS_OK;
  }
  idx_t options[METIS_NOPTIONS];
  std::copy(base_options, base_options + METIS_NOPTIONS, options);
  std::vector<idx_t> iperm(static_cast<size_t>(nv));
  MetisRandomScope rng;
  return METIS_NodeND(&nv, g.xadj.data(), g.adjncy.data(), nullptr, options, perm, iperm.data());
}

// The subgraph induced by the vertices with part[v] == which; local[v] is v's index in it.
Graph induced(const Graph& g, const std::vector<idx_t>& part, idx_t which, const std::vector<idx_t>& local,
              std::vector<idx_t>& global) {
  Graph h;
  h.xadj.push_back(0);
  for (idx_t v = 0; v < g.n(); ++v) {
    if (part[v] != which) continue;
    global.push_back(v);
    for (idx_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (part[g.adjncy[p]] == which) h.adjncy.push_back(local[g.adjncy[p]]);
    h.xadj.push_back(static_cast<idx_t>(h.adjncy.size()));
  }
  return h;
}

// Top separator, then the halves (at once when allowed); separator last.
// Between the METIS calls a raised cancel flag stops the ordering.
int split_and_order(Graph& g, const idx_t* options, bool two_threads, const RunContext& ctx, idx_t* order) {
  idx_t nv = g.n();
  std::vector<idx_t> part(static_cast<size_t>(nv));
  idx_t sepsize = 0;
  idx_t sep_options[METIS_NOPTIONS];
  std::copy(options, options + METIS_NOPTIONS, sep_options);
  int r;
  {
    MetisRandomScope rng;
    r = METIS_ComputeVertexSeparator(&nv, g.xadj.data(), g.adjncy.data(), nullptr, sep_options, &sepsize, part.data());
  }
  if (r != METIS_OK) return r;
  check_cancel_during_metis(ctx);
  std::vector<idx_t> local(static_cast<size_t>(nv));
  idx_t count[3] = {0, 0, 0};
  for (idx_t v = 0; v < nv; ++v) local[v] = count[part[v]]++;
  std::vector<idx_t> global0, global1;
  Graph h0 = induced(g, part, 0, local, global0);
  Graph h1 = induced(g, part, 1, local, global1);
  std::vector<idx_t> p0(global0.size()), p1(global1.size());
  int r1 = METIS_OK;
  if (two_threads && !global0.empty() && !global1.empty()) {
    // oneTBB threads of the caller's arena; one METIS call never waits on
    // oneTBB, so a thread cannot start the other half inside this one's scope.
    tbb::parallel_invoke([&] { r = node_nd(h0, options, p0.data()); },
                         [&] { r1 = node_nd(h1, options, p1.data()); });
  } else {
    r = node_nd(h0, options, p0.data());
    if (r == METIS_OK) {
      check_cancel_during_metis(ctx);
      r1 = node_nd(h1, options, p1.data());
    }
  }
  if (r != METIS_OK) return r;
  if (r1 != METIS_OK) return r1;
  size_t k = 0;
  for (const idx_t v : p0) order[k++] = global0[v];
  for (const idx_t v : p1) order[k++] = global1[v];
  for (idx_t v = 0; v < nv; ++v)
    if (part[v] == 2) order[k++] = v;
  return METIS_OK;
}

}  // namespace

Ordering order_matrix(const CscMatrix& A, const OrderingOptions& opt, const RunContext& ctx) {
  if (A.nrows != A.ncols) fail(ErrorCode::BadUsage, "order_matrix: matrix is not square");
  const int32_t n = A.ncols;
  Ordering o;
  o.perm.resize(n);
  o.iperm.resize(n);
  if (opt.method == OrderingOptions::Method::Natural || n <= 2) {
    std::iota(o.perm.begin(), o.perm.end(), 0);
    o.iperm = o.perm;
    return o;
  }
  Graph g;
  matrix_graph(A, g.xadj, g.adjncy);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_SEED] = opt.seed;
  options[METIS_OPTION_COMPRESS] = 0;
  const bool parallel = ctx.threads != 1 && (ctx.threads > 1 || tbb::this_task_arena::max_concurrency() > 1);
  ctx.check_cancel();
  std::vector<idx_t> order(static_cast<size_t>(n));
  const int rc = n < kSplitMinVertices ? node_nd(g, options, order.data())
                                       : split_and_order(g, options, parallel, ctx, order.data());
  if (rc != METIS_OK)
    fail(rc == METIS_ERROR_MEMORY ? ErrorCode::ResourceLimit : ErrorCode::Internal,
         "METIS_NodeND failed with status " + std::to_string(rc) + " on a graph of " + std::to_string(n) + " vertices");
  // METIS manual: row i of the permuted matrix is row perm[i] of the original,
  // which is our convention too.
  o.perm.assign(order.begin(), order.end());
  for (int32_t k = 0; k < n; ++k) o.iperm[o.perm[k]] = k;
  return o;
}

}  // namespace locus
