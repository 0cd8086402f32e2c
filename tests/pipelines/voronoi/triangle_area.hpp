// A triangle's area from its corner positions, for the remesh tests' checks
// (computed here, not by the library the tests check).
#pragma once
#include <cmath>
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus::test {

inline double triangle_area(const Mesh& m, int32_t f) {
  const int32_t a = m.f0[f], b = m.f1[f], c = m.f2[f];
  const double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], uz = m.z[b] - m.z[a];
  const double vx = m.x[c] - m.x[a], vy = m.y[c] - m.y[a], vz = m.z[c] - m.z[a];
  return 0.5 * std::hypot(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx);
}

}  // namespace locus::test
