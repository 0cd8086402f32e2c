// From the heat log map's gradient estimates to its output (pipelines/include/locus/pipelines/geodesic/logmap.hpp;
// thesis §6.6): the recenter shift (logmap_recenter.cpp), the raw angles, the
// lattice or Path offsets (logmap_lattice.cpp, logmap_path.cpp) and polar to
// Cartesian. The same for the localized and the full query, after every
// gradient and the distances.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <xsimd/xsimd.hpp>

#include "locus/pipelines/geodesic/logmap.hpp"
#include "logmap_parts.hpp"

namespace locus {

namespace {
// Below this |g|^2 (the plain average of far, tiny heat values) the squares
// may underflow: the length is taken by hypot instead.
constexpr double kTinyGradient2 = 1e-280;

// Raw angles of the (recentered by (bx, by)) gradient directions, a SIMD batch
// of vertices at a time (xsimd::atan2, see docs/logmap.md): aw.theta holds the
// angle per patch vertex, then the recentered gradients' x and y (each padded
// to whole batches; returned: the padded length).
size_t raw_angles(size_t np, double bx, double by, const LogMapEstimatorWorkspace& ew, LogMapAnglesWorkspace& aw) {
  using batch = xsimd::batch<double>;
  constexpr size_t Bw = batch::size;
  const size_t npad = (np + Bw - 1) / Bw * Bw;
  aw.theta.resize(3 * npad);
  double* gxs = aw.theta.data() + npad;
  double* gys = gxs + npad;
  for (size_t p = 0; p < np; ++p) {
    const bool usable = ew.use[p] != GradientUse::Plain;
    gxs[p] = ew.grad[2 * p] - (usable ? bx : 0.0);
    gys[p] = ew.grad[2 * p + 1] - (usable ? by : 0.0);
  }
  std::fill(gxs + np, gxs + npad, 0.0);
  std::fill(gys + np, gys + npad, 0.0);
  for (size_t p = 0; p < npad; p += Bw) {
    const batch gx = batch::load_unaligned(gxs + p), gy = batch::load_unaligned(gys + p);
    const auto zero = gx == batch(0.0) && gy == batch(0.0);
    xsimd::select(zero, batch(0.0), xsimd::atan2(gy, gx)).store_unaligned(aw.theta.data() + p);
  }
  return npad;
}
}  // namespace

void HeatLogMap::finish_angles(std::span<const int32_t> patch, const LogMapOutput& out, const LogMapEstimator& est,
                               LogMapStats& st, LogMapWorkspace& ws) const {
  const LogMapEstimatorWorkspace& ew = ws.estimator;
  LogMapPathWorkspace& pw = ws.path;
  HostVector<double>& theta = ws.angles.theta;
  const bool use_log = est.angle != LogMapAngle::HeatAverage;
  double bx = 0, by = 0;
  if (est.recenter && use_log && fit_recenter(patch, ew, bx, by)) st.recentered = true;
  const size_t npad = raw_angles(patch.size(), bx, by, ew, ws.angles);
  const double* gxs = theta.data() + npad;  // the recentered gradient per patch vertex
  const double* gys = gxs + npad;
  const double* lattice = use_log && !ws.lattice.table.empty() ? ws.lattice.table.data() : nullptr;
  // Path correction: first-pass angles (raw + the center's table), then the
  // offsets of the lattice along each ray replace the table's.
  const bool path = lattice && est.lattice == LatticeCorrection::Path;
  if (path) {
    pw.angle.resize(patch.size());
    for (size_t p = 0; p < patch.size(); ++p)
      pw.angle[p] = std::remainder(theta[p] + lattice_offset(lattice, theta[p]), 2 * std::numbers::pi);
    path_offsets(patch, ew.sources[0], pw);
  }
  for (size_t p = 0; p < patch.size(); ++p) {
    const bool usable = ew.use[p] != GradientUse::Plain;
    const double gx = gxs[p], gy = gys[p];
    double th = theta[p];
    if (!(lattice && usable) && (gx != 0 || gy != 0)) {
      // Polar to Cartesian from the direction itself (no cos / sin calls).
      const double g2 = gx * gx + gy * gy;
      const double il = g2 > kTinyGradient2 ? 1 / std::sqrt(g2) : 1 / std::hypot(gx, gy);
      out.angle[p] = th;
      out.u[p] = gx * il;  // unit direction; scale_by_distance makes it (u, v)
      out.v[p] = gy * il;
      continue;
    }
    if (path && usable && (gx != 0 || gy != 0)) {
      th += path_offset_at(pw.table, th, pw.r[p], pw.rmax);
      th = std::remainder(th, 2 * std::numbers::pi);
    } else if (lattice && usable && (gx != 0 || gy != 0)) {
      th = std::remainder(th + lattice_offset(lattice, th), 2 * std::numbers::pi);
    }
    out.angle[p] = th;
    out.u[p] = std::cos(th);
    out.v[p] = std::sin(th);
  }
}

// Polar to Cartesian: finish_angles left the unit direction in (u, v), which
// needs no distance.
void HeatLogMap::scale_by_distance(const LogMapOutput& out) {
  for (size_t p = 0; p < out.u.size(); ++p) {
    out.u[p] *= out.distance[p];
    out.v[p] *= out.distance[p];
  }
}

}  // namespace locus
