// Elimination trees (thesis §4.2): parent pointers, postorder and height.
//
// The graph is given as a symmetric adjacency in CSR (ptr[n+1], idx[]), in the
// numbering of the factor; for column k only neighbors i < k matter.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/core/host_allocator.hpp"

namespace locus {

// Liu's algorithm with path compression: O(nnz * alpha(n)). parent[k] = -1 at roots.
HostVector<int32_t> elimination_tree(int32_t n, std::span<const int64_t> ptr, std::span<const int32_t> idx);
// Postorder of a forest with parent[j] > j or -1; children in ascending order.
// post[k] = node visited k-th.
HostVector<int32_t> tree_postorder(std::span<const int32_t> parent);
// Nodes on the longest leaf-to-root path (a single node has height 1); needs parent[j] > j.
int32_t tree_height(std::span<const int32_t> parent);

}  // namespace locus
