// AMD orderings (kernels/include/locus/kernels/order/minimum_degree.hpp).
//
// AMD's default controls: aggressive absorption on, and a vertex of degree
// above 10 sqrt(n) set aside as dense and ordered last (never the case for
// mesh graphs above a few dozen vertices).
#include "locus/kernels/order/minimum_degree.hpp"

#include <amd.h>
#include <camd.h>

#include <algorithm>
#include <climits>
#include <numeric>
#include <string>

#include "locus/error.hpp"

namespace locus {

HostVector<int32_t> minimum_degree_order(const AdjacencyGraph& g) {
  const int32_t n = g.n();
  HostVector<int32_t> perm(static_cast<size_t>(n));
  if (n == 0) return perm;
  if (g.adj.empty()) {  // no edges: no fill whatever the order
    std::iota(perm.begin(), perm.end(), 0);
    return perm;
  }
  // amd_2 directly: amd_order would check the input, form A + A^T and copy
  // it, all of which an AdjacencyGraph already is (symmetric, no diagonal,
  // no duplicates); amd_2 needs a copy it may overwrite, with elbow room.
  double control[AMD_CONTROL], info[AMD_INFO];
  amd_defaults(control);
  const int64_t nnz = g.xadj[n];
  const int64_t iwlen = nnz + nnz / 5 + 2 * static_cast<int64_t>(n);  // amd_2 needs >= nnz + n
  if (iwlen > INT32_MAX)
    fail(ErrorCode::ResourceLimit, "AMD ordering: a graph of " + std::to_string(nnz) + " edges exceeds 32-bit indices");
  HostVector<int32_t> pe(g.xadj.begin(), g.xadj.end() - 1), len(n), iw(static_cast<size_t>(iwlen));
  HostVector<int32_t> nv(n), next(n), head(n), elen(n), degree(n), w(n);
  for (int32_t v = 0; v < n; ++v) len[v] = g.degree(v);
  std::copy(g.adj.begin(), g.adj.end(), iw.begin());
  amd_2(n, pe.data(), iw.data(), len.data(), static_cast<int>(iwlen), static_cast<int>(nnz), nv.data(), next.data(),
        perm.data(), head.data(), elen.data(), degree.data(), w.data(), control, info);
  return perm;
}

HostVector<int32_t> constrained_minimum_degree_order(const AdjacencyGraph& g, const HostVector<int32_t>& constraint) {
  const int32_t n = g.n();
  HostVector<int32_t> perm(static_cast<size_t>(n));
  if (constraint.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "CAMD ordering: " + std::to_string(constraint.size()) + " constraints for " +
                                  std::to_string(n) + " vertices");
  for (int32_t v = 0; v < n; ++v)
    if (constraint[v] < 0 || constraint[v] >= n)
      fail(ErrorCode::BadUsage, "CAMD ordering: constraint " + std::to_string(constraint[v]) + " of vertex " +
                                    std::to_string(v) + " is outside [0, " + std::to_string(n) + ")");
  if (n == 0) return perm;
  if (g.adj.empty()) {  // no edges: the constraint sets in turn, each in index order
    std::iota(perm.begin(), perm.end(), 0);
    std::stable_sort(perm.begin(), perm.end(), [&](int32_t a, int32_t b) { return constraint[a] < constraint[b]; });
    return perm;
  }
  // camd_2 directly, as amd_2 above: camd_order would check the input, count
  // and form A + A^T and copy it into fresh memory at every leaf of the
  // nested dissection (0.05 s of the ordering's CPU at 416k,
  // docs/ordering.md). With each list ascending, camd_order would build
  // exactly these lists (a vertex's smaller neighbors, then its larger ones,
  // each in order), so the order is the same as its.
  double control[CAMD_CONTROL], info[CAMD_INFO];
  camd_defaults(control);
  const int64_t nnz = g.xadj[n];
  const int64_t iwlen = nnz + nnz / 5 + static_cast<int64_t>(n);  // camd_2 needs >= nnz + n
  if (iwlen > INT32_MAX)
    fail(ErrorCode::ResourceLimit, "CAMD ordering: a graph of " + std::to_string(nnz) + " edges exceeds 32-bit indices");
  HostVector<int32_t> pe(g.xadj.begin(), g.xadj.end() - 1), len(n), iw(static_cast<size_t>(iwlen));
  HostVector<int32_t> nv(n), last(n), head(n + 1), elen(n), degree(n), w(n + 1), bucket_set(n);
  for (int32_t v = 0; v < n; ++v) len[v] = g.degree(v);
  std::copy(g.adj.begin(), g.adj.end(), iw.begin());
  camd_2(n, pe.data(), iw.data(), len.data(), static_cast<int>(iwlen), static_cast<int>(nnz), nv.data(), last.data(),
         perm.data(), head.data(), elen.data(), degree.data(), w.data(), control, info, constraint.data(),
         bucket_set.data());
  return perm;
}

}  // namespace locus
