// Analytic surfaces of the accuracy benchmarks (thesis §6.7, Table 6.8.1), with
// their exact geodesic distance and azimuth: `locus-bench logmap-accuracy` and
// `geodesic-accuracy` take one as their mesh-file argument, a spec KIND:SIZE:
//   icosphere:L        unit icosphere, level L (7: ~164k vertices, h ~ 0.0094)
//   random-sphere:N    convex hull of N random unit vectors (irregular)
//   cube-sphere:N      cube with N x N quads per face projected on the unit sphere
//                      (polygons); cube-sphere-tri:N triangulated
//   bump:R             z = exp(-(x^2 + y^2) / sigma^2) over the disk of radius 1.5
//                      (R rings, h ~ 1.5 / R), center at the top
// Exact values: on the sphere d = acos(p_c . p_j) and the azimuth of p_j in the
// tangent plane of p_c; on the bump the azimuth atan2(y, x) and the arc length
// of the radial profile by Simpson quadrature.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "locus/mesh.hpp"

namespace locus::bench {

struct Surface {
  Mesh mesh;
  std::string kind;  // "sphere" or "bump"
  double sigma = 0.5;
  std::vector<double> profile_r, profile_s;  // bump: arc length s(r) on a fine grid
  double exact_distance(int32_t c, int32_t j) const {
    if (kind == "sphere") {
      const double d = mesh.x[c] * mesh.x[j] + mesh.y[c] * mesh.y[j] + mesh.z[c] * mesh.z[j];
      const double nc = std::sqrt(mesh.x[c] * mesh.x[c] + mesh.y[c] * mesh.y[c] + mesh.z[c] * mesh.z[c]);
      const double nj = std::sqrt(mesh.x[j] * mesh.x[j] + mesh.y[j] * mesh.y[j] + mesh.z[j] * mesh.z[j]);
      return std::acos(std::clamp(d / (nc * nj), -1.0, 1.0));
    }
    const double r = std::hypot(mesh.x[j], mesh.y[j]);
    const double step = profile_r[1] - profile_r[0];
    const size_t k = std::min(profile_r.size() - 2, static_cast<size_t>(r / step));
    const double w = (r - profile_r[k]) / step;
    return profile_s[k] * (1 - w) + profile_s[k + 1] * w;
  }
};

// The surface a spec names; BadUsage for an unknown kind or a bad size.
Surface make_surface(const std::string& spec);

// Exact azimuth of j around c (up to a global rotation).
double exact_angle(const Surface& s, int32_t c, int32_t j);

}  // namespace locus::bench
