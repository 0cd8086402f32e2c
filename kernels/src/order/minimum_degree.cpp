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
  if (n == 0) return perm;
  double control[CAMD_CONTROL], info[CAMD_INFO];
  camd_defaults(control);
  const int rc = camd_order(n, g.xadj.data(), g.adj.data(), perm.data(), control, info, constraint.data());
  if (rc == CAMD_OUT_OF_MEMORY)
    fail(ErrorCode::ResourceLimit, "CAMD ordering: out of memory on a graph of " + std::to_string(n) + " vertices");
  if (rc != CAMD_OK && rc != CAMD_OK_BUT_JUMBLED)
    fail(ErrorCode::Internal, "CAMD ordering failed with status " + std::to_string(rc) + " on a graph of " +
                                  std::to_string(n) + " vertices");
  return perm;
}

}  // namespace locus
