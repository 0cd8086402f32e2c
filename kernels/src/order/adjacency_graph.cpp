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
  AdjacencyGraph h;
  h.xadj.resize(global.size() + 1);
  h.xadj[0] = 0;
  int64_t edges = 0;
  for (size_t k = 0; k < global.size(); ++k) {
    const int32_t v = global[k];
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) edges += part[g.adj[p]] == which;
  }
  h.adj.resize(static_cast<size_t>(edges));
  int32_t e = 0;
  for (size_t k = 0; k < global.size(); ++k) {
    const int32_t v = global[k];
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (part[g.adj[p]] == which) h.adj[e++] = local[g.adj[p]];
    h.xadj[k + 1] = e;
  }
  return h;
}

}  // namespace locus
