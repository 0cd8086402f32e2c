// Column counts of the Cholesky factor without forming it (Gilbert, Ng & Peyton
// 1994): every row subtree T_r(i) is represented by its leaves; a column's count
// is the number of row subtrees containing it, accumulated bottom-up from
// per-node differences. O(nnz(A) * alpha(n)) time.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/symbolic/subtree_partition.hpp"

namespace locus {

// Graph in CSR (symmetric adjacency, factor numbering), etree parent[] and its
// postorder. Returns nnz of each column of L, diagonal included.
HostVector<int32_t> column_counts(int32_t n, std::span<const int64_t> ptr, std::span<const int32_t> idx,
                                   std::span<const int32_t> parent, std::span<const int32_t> post);

// The same counts for a postordered etree (post = identity), the pieces of
// `part` (a partition of this etree) swept as parallel oneTBB tasks of the
// caller's arena, then the top nodes. Each piece keeps the row subtrees of its
// own rows; for rows above it, it hands over its first and last leaf, and the
// top sweep links those to the leaves before (their least common ancestors
// are top nodes). Equal to column_counts() for every partition.
HostVector<int32_t> column_counts_postordered(int32_t n, std::span<const int64_t> ptr, std::span<const int32_t> idx,
                                              std::span<const int32_t> parent, const SubtreePartition& part);

}  // namespace locus
