// Dual-triangulation angles and cell-area spread of a tessellation
// (pipelines/include/locus/pipelines/voronoi/cvt_quality.hpp; thesis §3.7.1, Table 3.7.1).
#include "locus/pipelines/voronoi/cvt_quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

double smallest_angle_deg(const std::array<double, 3>& a, const std::array<double, 3>& b,
                          const std::array<double, 3>& c) {
  const std::array<double, 3>* p[3] = {&a, &b, &c};
  double best = 180;
  for (int k = 0; k < 3; ++k) {
    const auto& o = *p[k];
    const auto& u = *p[(k + 1) % 3];
    const auto& w = *p[(k + 2) % 3];
    double d1[3], d2[3];
    for (int i = 0; i < 3; ++i) {
      d1[i] = u[i] - o[i];
      d2[i] = w[i] - o[i];
    }
    // atan2(|d1 x d2|, d1 . d2): accurate for small and large angles alike.
    const double cx = d1[1] * d2[2] - d1[2] * d2[1], cy = d1[2] * d2[0] - d1[0] * d2[2],
                 cz = d1[0] * d2[1] - d1[1] * d2[0];
    const double ang = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2]);
    best = std::min(best, ang * 180.0 / M_PI);
  }
  return best;
}

}  // namespace

void cell_area_spread(std::span<const double> area, double& cv, double& variance) {
  cv = variance = 0;
  if (area.empty()) return;
  double total = 0;
  for (double a : area) total += a;
  const double mean = total / static_cast<double>(area.size());
  double var = 0;
  for (double a : area) var += (a - mean) * (a - mean);
  var /= static_cast<double>(area.size());
  cv = mean > 0 ? std::sqrt(var) / mean : 0.0;
  variance = total > 0 ? var / (total * total) : 0.0;
}

CvtQuality cvt_quality(const Mesh& m, std::span<const int32_t> label, std::span<const SurfacePoint> sites) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(sites.size());
  if (label.size() != static_cast<size_t>(n)) fail(ErrorCode::BadUsage, "cvt quality: one label per vertex expected");
  for (int32_t v = 0; v < n; ++v)
    if (label[v] < 0 || label[v] >= ns)
      fail(ErrorCode::BadUsage, "cvt quality: vertex " + std::to_string(v) + " has label " + std::to_string(label[v]) +
                                    ", outside 0.." + std::to_string(ns - 1));
  CvtQuality q;
  const auto mass = lumped_mass(m);
  q.cell_area.assign(ns, 0.0);
  for (int32_t v = 0; v < n; ++v) q.cell_area[label[v]] += mass[v];
  double total = 0;
  for (double a : q.cell_area) total += a;
  const double mean = total / ns;
  double var = 0;
  for (double a : q.cell_area) {
    var += (a - mean) * (a - mean);
    q.empty_cells += a == 0;
  }
  var /= ns;
  q.area_cv = mean > 0 ? std::sqrt(var) / mean : 0.0;
  q.area_variance = total > 0 ? var / (total * total) : 0.0;

  std::vector<std::array<int32_t, 3>> tri;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    std::array<int32_t, 3> l = {label[m.f0[f]], label[m.f1[f]], label[m.f2[f]]};
    if (l[0] == l[1] || l[1] == l[2] || l[0] == l[2]) continue;
    std::sort(l.begin(), l.end());
    tri.push_back(l);
  }
  std::sort(tri.begin(), tri.end());
  tri.erase(std::unique(tri.begin(), tri.end()), tri.end());
  std::vector<std::array<double, 3>> pos(ns);
  for (int32_t s = 0; s < ns; ++s) pos[s] = surface_point_position(m, sites[s]);
  q.dual_triangles = static_cast<int64_t>(tri.size());
  double sum = 0, mn = 180;
  for (const auto& t : tri) {
    const double a = smallest_angle_deg(pos[t[0]], pos[t[1]], pos[t[2]]);
    sum += a;
    if (a < mn) q.min_angle_sites = t;
    mn = std::min(mn, a);
    ++q.angle_histogram[std::clamp(static_cast<int>(a / 5), 0, 11)];
  }
  q.min_angle_deg = tri.empty() ? 0.0 : mn;
  q.mean_angle_deg = tri.empty() ? 0.0 : sum / static_cast<double>(tri.size());
  return q;
}

}  // namespace locus
