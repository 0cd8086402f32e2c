// A triangle's vector area (twice its area times its unit normal) from its
// three corners (thesis §2.2: the normals of the cotan operator's faces). One
// term of face_vector_area's fan, for callers that hold a triangle's corners
// rather than a face id (the cvt reads f0/f1/f2 while face_vertices is lent out).
#pragma once

#include <array>
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus {

inline std::array<double, 3> triangle_vector_area(const Mesh& m, int32_t o, int32_t p, int32_t q) {
  const double ux = m.x[p] - m.x[o], uy = m.y[p] - m.y[o], uz = m.z[p] - m.z[o];
  const double wx = m.x[q] - m.x[o], wy = m.y[q] - m.y[o], wz = m.z[q] - m.z[o];
  double ax = 0, ay = 0, az = 0;  // from zero, as face_vector_area sums: the same bits
  ax += uy * wz - uz * wy;
  ay += uz * wx - ux * wz;
  az += ux * wy - uy * wx;
  return {ax, ay, az};
}

}  // namespace locus
