// The vertex farthest along direction d: handle picks of the skinning tests.
#pragma once
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus::test {

inline int32_t extreme_vertex(const Mesh& m, const double d[3]) {
  int32_t best = 0;
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (m.x[v] * d[0] + m.y[v] * d[1] + m.z[v] * d[2] > m.x[best] * d[0] + m.y[best] * d[1] + m.z[best] * d[2])
      best = v;
  return best;
}

}  // namespace locus::test
