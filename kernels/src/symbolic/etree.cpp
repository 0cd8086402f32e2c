// Elimination tree, postorder and height (kernels/include/locus/kernels/symbolic/etree.hpp).
#include "locus/kernels/symbolic/etree.hpp"
#include "locus/core/host_allocator.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

#include <algorithm>

namespace locus {

HostVector<int32_t> elimination_tree(int32_t n, std::span<const int64_t> ptr, std::span<const int32_t> idx) {
  HostVector<int32_t> parent(n, -1), ancestor(n, -1);
  for (int32_t k = 0; k < n; ++k) {
    cancel_point(k);
    for (int64_t p = ptr[k]; p < ptr[k + 1]; ++p) {
      int32_t r = idx[p];
      if (r >= k) continue;
      // Climb from r to the root of its current subtree, pointing the path at k.
      while (ancestor[r] != -1 && ancestor[r] != k) {
        const int32_t next = ancestor[r];
        ancestor[r] = k;
        r = next;
      }
      if (ancestor[r] == -1) {
        ancestor[r] = k;
        parent[r] = k;
      }
    }
  }
  return parent;
}

HostVector<int32_t> tree_postorder(std::span<const int32_t> parent) {
  const int32_t n = static_cast<int32_t>(parent.size());
  HostVector<int32_t> head(n, -1), next(n, -1), post;
  post.reserve(n);
  for (int32_t j = n - 1; j >= 0; --j) {  // push in descending order -> lists ascending
    const int32_t p = parent[j];
    if (p < 0) continue;
    next[j] = head[p];
    head[p] = j;
  }
  HostVector<int32_t> stack;
  for (int32_t root = 0; root < n; ++root) {
    if (parent[root] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int32_t j = stack.back();
      const int32_t c = head[j];
      if (c == -1) {
        stack.pop_back();
        post.push_back(j);
      } else {
        head[j] = next[c];  // consume child c
        stack.push_back(c);
      }
    }
  }
  return post;
}

int32_t tree_height(std::span<const int32_t> parent) {
  const int32_t n = static_cast<int32_t>(parent.size());
  HostVector<int32_t> depth(n, 1);
  int32_t h = 0;
  for (int32_t j = n - 1; j >= 0; --j) {
    if (parent[j] >= 0) depth[j] = depth[parent[j]] + 1;
    h = std::max(h, depth[j]);
  }
  return h;
}

}  // namespace locus
