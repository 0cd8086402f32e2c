// Column counts by row-subtree leaves (kernels/include/locus/kernels/symbolic/column_counts.hpp).
//
// For each row i, the leaves of its row subtree are the columns j < i with
// A_ij != 0 whose subtree does not contain an earlier such column (tested with
// first-descendant indices in postorder). Each leaf adds one to its column;
// the least common ancestor of consecutive leaves subtracts one (found with a
// disjoint-set forest over processed nodes). Each non-root node subtracts one
// from its parent, and summing over subtrees gives the counts.
#include "locus/kernels/symbolic/column_counts.hpp"
#include "locus/core/host_allocator.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

HostVector<int32_t> column_counts(int32_t n, std::span<const int64_t> ptr, std::span<const int32_t> idx,
                                   std::span<const int32_t> parent, std::span<const int32_t> post) {
  HostVector<int32_t> delta(n, 0), first(n, -1), maxfirst(n, -1), prevleaf(n, -1), ancestor(n);
  for (int32_t k = 0; k < n; ++k) {
    int32_t j = post[k];
    delta[j] = (first[j] == -1) ? 1 : 0;  // etree leaves start with their diagonal
    for (; j != -1 && first[j] == -1; j = parent[j]) first[j] = k;
  }
  for (int32_t i = 0; i < n; ++i) ancestor[i] = i;
  for (int32_t k = 0; k < n; ++k) {
    cancel_point(k);
    const int32_t j = post[k];
    if (parent[j] != -1) --delta[parent[j]];
    for (int64_t p = ptr[j]; p < ptr[j + 1]; ++p) {
      const int32_t i = idx[p];
      if (i <= j || first[j] <= maxfirst[i]) continue;  // j is not a leaf of T_r(i)
      maxfirst[i] = first[j];
      const int32_t jprev = prevleaf[i];
      prevleaf[i] = j;
      ++delta[j];
      if (jprev != -1) {
        // q = root of jprev's set = least common ancestor of jprev and j.
        int32_t q = jprev;
        while (q != ancestor[q]) q = ancestor[q];
        for (int32_t s = jprev; s != q;) {  // path compression
          const int32_t next = ancestor[s];
          ancestor[s] = q;
          s = next;
        }
        --delta[q];
      }
    }
    if (parent[j] != -1) ancestor[j] = parent[j];
  }
  for (int32_t j = 0; j < n; ++j)  // parent[j] > j: ascending order sums children first
    if (parent[j] != -1) delta[parent[j]] += delta[j];
  return delta;
}

}  // namespace locus
