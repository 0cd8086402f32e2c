// Distances by brute force, for the remesh tests' oracles (computed here, not
// by the library the tests check): a point to a triangle (the plane when the
// point projects inside, else the nearest of the three edges), and a point to
// every triangle of a mesh; and a mesh's smallest angle.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "locus/mesh.hpp"

namespace locus::test {

using P3 = std::array<double, 3>;

inline P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline P3 at(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }

inline double tri_distance(const P3& p, const P3& a, const P3& b, const P3& c) {
  const P3 u = sub(b, a), v = sub(c, a), w = sub(p, a);
  const double uu = dot(u, u), uv = dot(u, v), vv = dot(v, v), wu = dot(w, u), wv = dot(w, v);
  const double den = uu * vv - uv * uv;
  const double s = (vv * wu - uv * wv) / den, t = (uu * wv - uv * wu) / den;
  if (s >= 0 && t >= 0 && s + t <= 1) {
    const P3 q = {a[0] + s * u[0] + t * v[0], a[1] + s * u[1] + t * v[1], a[2] + s * u[2] + t * v[2]};
    return std::sqrt(dot(sub(p, q), sub(p, q)));
  }
  auto seg = [&](const P3& x, const P3& y) {
    const P3 d = sub(y, x);
    const double l = std::clamp(dot(sub(p, x), d) / dot(d, d), 0.0, 1.0);
    const P3 q = {x[0] + l * d[0], x[1] + l * d[1], x[2] + l * d[2]};
    return std::sqrt(dot(sub(p, q), sub(p, q)));
  };
  return std::min({seg(a, b), seg(b, c), seg(c, a)});
}

inline double distance_to(const Mesh& m, const P3& p) {
  double d = HUGE_VAL;
  for (int32_t f = 0; f < m.num_faces(); ++f)
    d = std::min(d, tri_distance(p, at(m, m.f0[f]), at(m, m.f1[f]), at(m, m.f2[f])));
  return d;
}

// The smallest angle of any triangle of m, in degrees.
inline double smallest_angle_deg(const Mesh& m) {
  double best = 180;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const P3 p[3] = {at(m, m.f0[f]), at(m, m.f1[f]), at(m, m.f2[f])};
    for (int k = 0; k < 3; ++k) {
      const P3 a = sub(p[(k + 1) % 3], p[k]), b = sub(p[(k + 2) % 3], p[k]);
      best = std::min(best, std::acos(std::clamp(dot(a, b) / std::sqrt(dot(a, a) * dot(b, b)), -1.0, 1.0)) * 180 / M_PI);
    }
  }
  return best;
}

}  // namespace locus::test
