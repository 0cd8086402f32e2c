// Subtree partition of a postordered forest (kernels/include/locus/kernels/symbolic/subtree_partition.hpp).
#include "locus/kernels/symbolic/subtree_partition.hpp"

#include <algorithm>

namespace locus {

SubtreePartition subtree_partition(std::span<const int32_t> parent, HostVector<int64_t> weight,
                                   int64_t max_piece_weight) {
  const int32_t n = static_cast<int32_t>(parent.size());
  // Subtree weights and first descendants, children before parents (parent[j] > j).
  HostVector<int32_t> first(n);
  for (int32_t j = 0; j < n; ++j) first[j] = j;
  for (int32_t j = 0; j < n; ++j) {
    const int32_t p = parent[j];
    if (p < 0) continue;
    weight[p] += weight[j];
    first[p] = std::min(first[p], first[j]);
  }
  SubtreePartition part;
  int64_t last_weight = 0;  // of the piece being grown
  const auto is_top = [&](int32_t j) { return weight[j] > max_piece_weight; };
  for (int32_t j = 0; j < n; ++j) {
    if (is_top(j)) {
      part.top.push_back(j);
      continue;
    }
    if (parent[j] >= 0 && !is_top(parent[j])) continue;  // inside a larger piece
    // j roots a maximal light subtree [first[j], j]; join it to the previous
    // piece when they touch (no top node between) and stay within the bound.
    if (!part.piece_end.empty() && part.piece_end.back() == first[j] &&
        last_weight + weight[j] <= max_piece_weight) {
      part.piece_end.back() = j + 1;
      last_weight += weight[j];
    } else {
      part.piece_begin.push_back(first[j]);
      part.piece_end.push_back(j + 1);
      last_weight = weight[j];
    }
  }
  return part;
}

}  // namespace locus
