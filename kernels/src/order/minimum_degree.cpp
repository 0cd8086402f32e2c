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

namespace {

// What amd_2 and camd_2 take instead of a matrix: the graph's lists (Pe,
// Len) in a copy they may overwrite (Iw), with iwlen - nnz entries of elbow
// room (both need at least n). An AdjacencyGraph already is the A + A^T
// that amd_order / camd_order would form (symmetric, no diagonal, no
// duplicates).
struct MinimumDegreeInput {
  HostVector<int32_t> pe, len, iw;
  int iwlen = 0, nnz = 0;
};

MinimumDegreeInput minimum_degree_input(const AdjacencyGraph& g, int64_t elbow, const char* what) {
  const int32_t n = g.n();
  const int64_t nnz = g.xadj[n];
  const int64_t iwlen = nnz + nnz / 5 + elbow;
  if (iwlen > INT32_MAX)
    fail(ErrorCode::ResourceLimit,
         std::string(what) + " ordering: a graph of " + std::to_string(nnz) + " edges exceeds 32-bit indices");
  MinimumDegreeInput in;
  in.pe.assign(g.xadj.begin(), g.xadj.end() - 1);
  in.len.resize(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) in.len[v] = g.degree(v);
  in.iw.resize(static_cast<size_t>(iwlen));
  std::copy(g.adj.begin(), g.adj.end(), in.iw.begin());
  in.iwlen = static_cast<int>(iwlen);
  in.nnz = static_cast<int>(nnz);
  return in;
}

}  // namespace

HostVector<int32_t> minimum_degree_order(const AdjacencyGraph& g) {
  const int32_t n = g.n();
  HostVector<int32_t> perm(static_cast<size_t>(n));
  if (n == 0) return perm;
  if (g.adj.empty()) {  // no edges: no fill whatever the order
    std::iota(perm.begin(), perm.end(), 0);
    return perm;
  }
  // amd_2 directly: amd_order would check the input, form A + A^T and copy it.
  double control[AMD_CONTROL], info[AMD_INFO];
  amd_defaults(control);
  MinimumDegreeInput in = minimum_degree_input(g, 2 * static_cast<int64_t>(n), "AMD");
  HostVector<int32_t> nv(n), next(n), head(n), elen(n), degree(n), w(n);
  amd_2(n, in.pe.data(), in.iw.data(), in.len.data(), in.iwlen, in.nnz, nv.data(), next.data(), perm.data(),
        head.data(), elen.data(), degree.data(), w.data(), control, info);
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
  MinimumDegreeInput in = minimum_degree_input(g, n, "CAMD");
  HostVector<int32_t> nv(n), last(n), head(n + 1), elen(n), degree(n), w(n + 1), bucket_set(n);
  camd_2(n, in.pe.data(), in.iw.data(), in.len.data(), in.iwlen, in.nnz, nv.data(), last.data(), perm.data(),
         head.data(), elen.data(), degree.data(), w.data(), control, info, constraint.data(), bucket_set.data());
  return perm;
}

}  // namespace locus
