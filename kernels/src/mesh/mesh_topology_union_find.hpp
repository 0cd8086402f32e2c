// Disjoint sets over int32 ids for the topology kernels (components, fans around
// vertices). Path halving; the smaller id always becomes the root, so a root is
// the smallest member of its set and results depend only on the input order.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

namespace locus {

inline int32_t uf_find(std::vector<int32_t>& parent, int32_t a) {
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

// Returns true when a and b were in different sets (one set fewer now).
inline bool uf_unite(std::vector<int32_t>& parent, int32_t a, int32_t b) {
  a = uf_find(parent, a);
  b = uf_find(parent, b);
  if (a == b) return false;
  if (a < b) std::swap(a, b);
  parent[a] = b;
  return true;
}

}  // namespace locus
