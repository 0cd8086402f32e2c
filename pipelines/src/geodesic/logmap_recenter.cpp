// Recentering of the heat log map's gradients (LogMapOptions::recenter;
// pipelines/include/locus/pipelines/geodesic/logmap.hpp; thesis §6.6).
// Measurements: docs/logmap.md.
//
// Far from the stencil, grad log h_j at i is k*(direction of j) plus a part b
// that does not depend on j (the heat kernel's vertex-level factors around i
// on irregular meshes: each vertex's mass and weights scale the heat from
// every source alike). The k* lie on a closed convex curve around 0,
// centrally symmetric for a symmetric operator; a least-squares circle
// through the gradients (Kasa: |g|^2 = 2 b.g + c) estimates b. Only with
// directions all around the center and beyond the near field
// (GradientUse::FarField, logmap_estimator.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "locus/pipelines/geodesic/logmap.hpp"
#include "logmap_parts.hpp"

namespace locus {

namespace {
// Fewer far-field directions than this give no trustworthy circle.
constexpr int64_t kMinDirections = 16;
// "All around the center": the resultant of the unit directions below this
// fraction of their count (a one-sided patch has a resultant near 1).
constexpr double kMaxResultant = 0.25;
// A center shift of a third of the circle's radius or more is no small
// vertex-level bias: the raw gradients are kept (|b| < radius / kRadiusPerShift).
constexpr double kRadiusPerShift = 3;

double det3(const double M[3][3]) {
  return M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
         M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
}
}  // namespace

bool fit_recenter(std::span<const int32_t> patch, const LogMapEstimatorWorkspace& ws, double& bx, double& by) {
  const bool two_ring = !ws.coef2.empty();
  double N[3][3] = {}, r[3] = {}, ux = 0, uy = 0;
  int64_t cnt = 0;
  for (size_t p = 0; p < patch.size(); ++p) {
    if (ws.use[p] != GradientUse::FarField) continue;
    if (two_ring && std::binary_search(ws.sorted_sources.begin(), ws.sorted_sources.end(), patch[p])) continue;
    const double gx = ws.grad[2 * p], gy = ws.grad[2 * p + 1];
    const double g2 = gx * gx + gy * gy;
    if (!(g2 > 0)) continue;
    const double a[3] = {2 * gx, 2 * gy, 1.0};
    for (int i = 0; i < 3; ++i) {
      r[i] += a[i] * g2;
      for (int j = 0; j < 3; ++j) N[i][j] += a[i] * a[j];
    }
    const double il = 1 / std::sqrt(g2);
    ux += gx * il;
    uy += gy * il;
    ++cnt;
  }
  if (!(cnt >= kMinDirections && std::hypot(ux, uy) < kMaxResultant * static_cast<double>(cnt))) return false;
  // 3x3 solve by Cramer's rule (well conditioned when the directions go all round).
  const double D = det3(N);
  if (!(std::abs(D) > 0 && std::isfinite(D))) return false;
  double sol[3];
  for (int k = 0; k < 3; ++k) {
    double M[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) M[i][j] = j == k ? r[i] : N[i][j];
    sol[k] = det3(M) / D;
  }
  const double radius2 = sol[2] + sol[0] * sol[0] + sol[1] * sol[1];
  if (!(radius2 > 0 && sol[0] * sol[0] + sol[1] * sol[1] < radius2 / (kRadiusPerShift * kRadiusPerShift))) return false;
  bx = sol[0];
  by = sol[1];
  return true;
}

}  // namespace locus
