// Ordering graphs (kernels/include/locus/kernels/order/adjacency_graph.hpp).
#include "locus/kernels/order/adjacency_graph.hpp"

#include <string>

#include "locus/error.hpp"

namespace locus {

AdjacencyGraph adjacency_of(const CscMatrix& A) {
  const int32_t n = A.ncols;
  HostVector<int64_t> deg(static_cast<size_t>(n) + 1, 0);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i != j) { ++deg[i + 1]; ++deg[j + 1]; }
    }
  for (int32_t j = 0; j < n; ++j) deg[j + 1] += deg[j];
  if (deg[n] > INT32_MAX)
    fail(ErrorCode::ResourceLimit, "ordering: the graph of a " + std::to_string(n) + "-column matrix has " +
                                       std::to_string(deg[n]) + " directed edges (limit 2^31 - 1)");
  AdjacencyGraph g;
  g.xadj.assign(deg.begin(), deg.end());
  g.adj.resize(static_cast<size_t>(deg[n]));
  // Column j's rows i > j come ascending, and columns are visited ascending,
  // so each vertex receives its smaller neighbors first, ascending, then its
  // larger ones, ascending: every list comes out sorted.
  HostVector<int32_t> pos(g.xadj.begin(), g.xadj.end() - 1);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i != j) g.adj[pos[i]++] = j;
    }
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i != j) g.adj[pos[j]++] = i;
    }
  return g;
}

AdjacencyGraph induced_subgraph(const AdjacencyGraph& g, std::span<const int8_t> part, int8_t which,
                                HostVector<int32_t>& global) {
  const int32_t n = g.n();
  HostVector<int32_t> local(static_cast<size_t>(n), -1);
  global.clear();
  for (int32_t v = 0; v < n; ++v)
    if (part[v] == which) { local[v] = static_cast<int32_t>(global.size()); global.push_back(v); }
  // One pass over the rows: the adjacency is reserved for every edge of the
  // side's vertices (the few that cross to the separator are not kept)
  // instead of counted in a pass of its own.
  size_t bound = 0;
  for (const int32_t v : global) bound += static_cast<size_t>(g.xadj[v + 1] - g.xadj[v]);
  AdjacencyGraph h;
  h.xadj.resize(global.size() + 1);
  h.xadj[0] = 0;
  h.adj.reserve(bound);
  for (size_t k = 0; k < global.size(); ++k) {
    const int32_t v = global[k];
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (const int32_t l = local[g.adj[p]]; l >= 0) h.adj.push_back(l);
    h.xadj[k + 1] = static_cast<int32_t>(h.adj.size());
  }
  return h;
}

}  // namespace locus
