// The few 3-vector operations the remesh's geometry files share (positions as
// std::array, the remesh's own working type). Internal to the voronoi pipeline.
#pragma once
#include <algorithm>
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
// The angle at o between the directions to u and w, in radians (atan2: accurate near 0 and pi).
inline double angle_at(const V3& o, const V3& u, const V3& w) {
  const V3 a = sub(u, o), b = sub(w, o);
  return std::atan2(norm(cross(a, b)), dot(a, b));
}
inline V3 pos(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }
// A triangle's smallest angle, and its normal scaled by twice its area.
inline double min_angle(const V3& a, const V3& b, const V3& c) {
  return std::min({angle_at(a, b, c), angle_at(b, c, a), angle_at(c, a, b)});
}
inline V3 tri_normal(const V3& a, const V3& b, const V3& c) { return cross(sub(b, a), sub(c, a)); }

}  // namespace locus::remesh_vec3
