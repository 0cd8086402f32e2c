// The few 3-vector operations the remesh's geometry files share (positions as
// std::array, the remesh's own working type). Internal to the voronoi pipeline.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus::remesh_vec3 {

using V3 = std::array<double, 3>;
inline V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const V3& a) { return std::sqrt(dot(a, a)); }
inline V3 pos(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }

}  // namespace locus::remesh_vec3
