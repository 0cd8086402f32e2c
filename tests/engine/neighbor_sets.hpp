// Test oracle for the engine's rebuilt vertex adjacency (thesis §3.7.1: the
// CVT's loans of derived data): each vertex's neighbors as a std::set, from
// every face's consecutive corners, a repeated corner giving no self loop.
#pragma once

#include <doctest/doctest.h>

#include <cstdint>
#include <set>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"

namespace locus::test {

inline std::vector<std::set<int32_t>> neighbor_sets(const Mesh& m) {
  std::vector<std::set<int32_t>> want(static_cast<size_t>(m.num_vertices()));
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto face = m.face(f);
    for (size_t k = 0; k < face.size(); ++k) {
      const int32_t a = face[k], b = face[(k + 1) % face.size()];
      if (a == b) continue;
      want[a].insert(b);
      want[b].insert(a);
    }
  }
  return want;
}

// The adjacency's rows against the oracle, vertex by vertex.
inline void check_rows(const Adjacency& a, const std::vector<std::set<int32_t>>& want) {
  REQUIRE(a.offsets.size() == want.size() + 1);
  for (size_t v = 0; v < want.size(); ++v)
    CHECK(std::vector<int32_t>(a.neighbors.begin() + a.offsets[v], a.neighbors.begin() + a.offsets[v + 1]) ==
          std::vector<int32_t>(want[v].begin(), want[v].end()));
}

}  // namespace locus::test
