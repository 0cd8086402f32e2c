// Test fixture for the engine's loans of derived data (thesis §3.7.1: the cvt
// command on an exclusive Session lends its incidence, adjacency and corners
// out while it runs): two Sessions on copies of one mesh, one that lends
// nothing (the oracle) and one exclusive.
#pragma once

#include "locus/mesh.hpp"
#include "locus/session.hpp"

namespace locus::test {

inline SessionOptions exclusive_options() {
  SessionOptions o;
  o.exclusive = true;
  return o;
}

struct LendingSessions {
  explicit LendingSessions(const Mesh& m) : shared{Mesh(m)}, lent{Mesh(m), exclusive_options()} {}
  const Session shared, lent;
};

}  // namespace locus::test
