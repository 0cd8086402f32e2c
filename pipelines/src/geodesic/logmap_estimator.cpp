// The heat log map's angle estimators (pipelines/include/locus/pipelines/geodesic/logmap.hpp,
// "Angle estimator"; thesis §6.6, eqs. 6.7, 6.8): per center, the sources S and
// the coefficients that turn the heat from S at a vertex j into the direction
// to j (one-ring average, two-ring least-squares fit); per patch vertex, that
// direction from its heat row (the gradient estimate), with the log
// estimators' fallback to the plain average. Measurements behind the choices:
// docs/logmap.md.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <xsimd/xsimd.hpp>

#include "locus/pipelines/geodesic/logmap.hpp"
#include "logmap_parts.hpp"

namespace locus {

namespace {
// The near field of the center, where no gradient enters the recenter fit:
// heat from the center above e^-4 of its peak, about 4 edges at t = h^2. Told
// by the heat, not by the distance: the localized and the full map must see
// the same set.
constexpr double kNearFieldHeat = 0.0183;  // e^-4
// The two-ring fit's normal equations (6x6, coordinates in units of h) count
// as degenerate when their pivots span more than 12 orders of magnitude.
constexpr double kMinPivotRatio = 1e-12;
}  // namespace

// Sources S = {i} ∪ N(i) (i first, neighbors ascending; TwoRing: then the
// second ring, ascending) and the estimator coefficients in the frame (e1, e2):
// direction to j = (sum_k a_k f_k, sum_k b_k f_k), f_k = (h_k)_j or log (h_k)_j.
// One ring: a_k = W_k . e1, b_k = W_k . e2 with W_k = sum_{f ∋ i} A_f P grad(phi_k)_f,
// P = I - n n^T (eqs. 6.7, 6.8). Two ring: the gradient at i of the least-squares
// quadratic c + g.q + q^T H q / 2 through the values at the 2-ring, q_k the
// tangent-plane coordinates of vertex k; the quadratic terms absorb the
// curvature of log h_j (~ 1 / (r_j sqrt(t))) so that lopsided stencils do not
// turn it into a gradient bias.
LogMapEstimator HeatLogMap::prepare_center(int32_t i, LogMapEstimator est, LogMapWorkspace& ws) const {
  const TriangleGradients& g = geo_.gradients();
  LogMapEstimatorWorkspace& ew = ws.estimator;
  HostVector<int32_t>& S = ew.sources;
  S.clear();
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q)
    for (int s = 0; s < 3; ++s) S.push_back(g.tri[3 * static_cast<int64_t>(g.vf_faces[q]) + s]);
  std::sort(S.begin(), S.end());
  S.erase(std::unique(S.begin(), S.end()), S.end());
  S.erase(std::find(S.begin(), S.end(), i));
  S.insert(S.begin(), i);
  const size_t ring1 = S.size();
  // Auto: the two-ring fit at irregular stars; at shape-regular stars of a
  // valence other than 6 (lattice defects) the thesis' one-ring average of
  // grad h; the one-ring log estimator elsewhere. At a symmetric star the
  // one-ring estimator has no convexity bias, which is what the log removes
  // elsewhere, and there the average of grad h follows the heat better than the
  // log (icosphere 7, its 12 valence-5 corners: 5.3e-4 against 9.5e-4 at
  // t = 4 h^2; 1.08e-3 against 3.19e-3 at h^2; docs/logmap.md, "Defect centers").
  // The lattice correction only at regular valence-6 stars: an irregular star
  // (or ring of them) is no lattice, and on random-point spheres the correction
  // doubled the error (docs/logmap.md, "Angle estimators"); defects: see defect_star.
  const bool irregular = irregular_star(i), defect = !irregular && defect_star(i);
  if (est.angle == LogMapAngle::Auto)
    est.angle = irregular ? LogMapAngle::LogHeatTwoRing : (defect ? LogMapAngle::HeatAverage : LogMapAngle::LogHeat);
  if (irregular || defect_star(i)) est.lattice = LatticeCorrection::None;
  const LogMapAngle angle = est.angle;
  if (angle == LogMapAngle::LogHeatTwoRing) {
    HostVector<int32_t>& R2 = ew.ring2;
    R2.clear();
    for (size_t k = 1; k < ring1; ++k)
      for (int64_t q = g.vf_offsets[S[k]]; q < g.vf_offsets[S[k] + 1]; ++q)
        for (int s = 0; s < 3; ++s) R2.push_back(g.tri[3 * static_cast<int64_t>(g.vf_faces[q]) + s]);
    std::sort(R2.begin(), R2.end());
    R2.erase(std::unique(R2.begin(), R2.end()), R2.end());
    for (int32_t w : R2)
      if (std::find(S.begin(), S.begin() + ring1, w) == S.begin() + ring1) S.push_back(w);
  }
  const size_t d = S.size();
  double n[3], e1[3], e2[3];
  frame(i, n, e1, e2);
  ew.coef1.assign(2 * d, 0.0);
  double star_area = 0;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
    const int32_t f = g.vf_faces[q];
    star_area += g.area[f];
    const double* b = g.basis.data() + 9 * static_cast<int64_t>(f);
    for (int s = 0; s < 3; ++s) {
      const int32_t w = g.tri[3 * static_cast<int64_t>(f) + s];
      const size_t k = static_cast<size_t>(std::find(S.begin(), S.begin() + ring1, w) - S.begin());
      // P grad(phi) . e = grad(phi) . e for e in the tangent plane.
      ew.coef1[2 * k] += g.area[f] * dot3(b + 3 * s, e1);
      ew.coef1[2 * k + 1] += g.area[f] * dot3(b + 3 * s, e2);
    }
  }
  // Divided by the star's area: the average gradient itself (eq. 6.8 up to a
  // positive factor, same angle), whose magnitude the lattice correction needs.
  for (double& c : ew.coef1) c /= star_area;
  ws.lattice.table.clear();
  if (angle != LogMapAngle::HeatAverage && est.lattice != LatticeCorrection::None) {
    // Star: the center's own star; Ring: the stars of the center and its ring.
    const size_t stars = est.lattice == LatticeCorrection::Ring ? ring1 : 1;
    prepare_lattice(e1, e2, std::span<const int32_t>(S.data(), stars), ws.lattice);
  }
  ew.coef2.clear();
  if (angle == LogMapAngle::LogHeatTwoRing) two_ring_coefficients(i, e1, e2, ew);
  return est;
}

// LogHeatTwoRing: ew.coef2, the gradient at i of the least-squares quadratic
// through the values at the sources (i, its ring, its two-ring) in the
// tangent-plane frame (e1, e2); left empty for a degenerate stencil.
void HeatLogMap::two_ring_coefficients(int32_t i, const double e1[3], const double e2[3],
                                       LogMapEstimatorWorkspace& ew) const {
  const HostVector<int32_t>& S = ew.sources;
  const size_t d = S.size();
  // Normal equations of the quadratic fit in coordinates scaled by 1/h, solved
  // by a 6x6 Cholesky factorization (SPD unless the stencil is degenerate).
  const double inv_h = 1.0 / geo_.mean_edge_length();
  double N[6][6] = {};
  ew.phi.resize(6 * d);
  for (size_t k = 0; k < d; ++k) {
    const int32_t v = S[k];
    const double p[3] = {x_[v] - x_[i], y_[v] - y_[i], z_[v] - z_[i]};
    const double qx = dot3(p, e1) * inv_h, qy = dot3(p, e2) * inv_h;
    double* f = ew.phi.data() + 6 * k;
    f[0] = 1.0, f[1] = qx, f[2] = qy, f[3] = 0.5 * qx * qx, f[4] = qx * qy, f[5] = 0.5 * qy * qy;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c <= r; ++c) N[r][c] += f[r] * f[c];
  }
  double Lc[6][6] = {};
  double dmax = 0, dmin = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 6; ++c) {
    double diag = N[c][c];
    for (int k = 0; k < c; ++k) diag -= Lc[c][k] * Lc[c][k];
    if (!(diag > 0)) return;  // degenerate stencil: one-ring estimator only
    Lc[c][c] = std::sqrt(diag);
    dmax = std::max(dmax, diag);
    dmin = std::min(dmin, diag);
    for (int r = c + 1; r < 6; ++r) {
      double v = N[r][c];
      for (int k = 0; k < c; ++k) v -= Lc[r][k] * Lc[c][k];
      Lc[r][c] = v / Lc[c][c];
    }
  }
  if (!(dmin > kMinPivotRatio * dmax)) return;
  ew.coef2.resize(2 * d);
  for (size_t k = 0; k < d; ++k) {
    double y[6];
    const double* f = ew.phi.data() + 6 * k;
    for (int r = 0; r < 6; ++r) {
      double v = f[r];
      for (int c = 0; c < r; ++c) v -= Lc[r][c] * y[c];
      y[r] = v / Lc[r][r];
    }
    for (int r = 5; r >= 0; --r) {
      double v = y[r];
      for (int c = r + 1; c < 6; ++c) v -= Lc[c][r] * y[c];
      y[r] = v / Lc[r][r];
    }
    ew.coef2[2 * k] = y[1] * inv_h;
    ew.coef2[2 * k + 1] = y[2] * inv_h;
  }
}

void HeatLogMap::begin_gradients(size_t patch_size, LogMapEstimatorWorkspace& ew, LogMapPathWorkspace& pw) const {
  ew.sorted_sources.assign(ew.sources.begin(), ew.sources.end());
  std::sort(ew.sorted_sources.begin(), ew.sorted_sources.end());
  // Padded row buffer and de-interleaved coefficients (one-ring, then two-ring
  // or the one-ring again) for vertex_gradient's vector loop.
  const size_t d = ew.sources.size(), B = xsimd::batch<double>::size, dp = (d + B - 1) / B * B;
  ew.rowbuf.assign(dp, 0.0);
  ew.cpad.assign(4 * dp, 0.0);
  const HostVector<double>& c2 = ew.coef2.empty() ? ew.coef1 : ew.coef2;
  for (size_t k = 0; k < d; ++k) {
    ew.cpad[k] = ew.coef1[2 * k];
    ew.cpad[dp + k] = ew.coef1[2 * k + 1];
    ew.cpad[2 * dp + k] = c2[2 * k];
    ew.cpad[3 * dp + k] = c2[2 * k + 1];
  }
  ew.grad.resize(2 * patch_size);
  ew.use.resize(patch_size);
  pw.r.resize(patch_size);
}

// The log estimators' sum for one heat row f (|S| values; padded: zeros up
// to whole SIMD batches, else copied into ew.rowbuf first) with the
// coefficients at cx, cy (ew.cpad). Logs in bulk, both components in vector
// accumulators. False when a used source (non-zero coefficient) has
// non-positive heat: the caller then takes the plain average.
namespace {
bool log_gradient(const double* f, bool padded, const double* cx, const double* cy, LogMapEstimatorWorkspace& ew,
                  double& gx, double& gy) {
  using batch = xsimd::batch<double>;
  constexpr size_t B = batch::size;
  const size_t d = ew.sources.size(), dp = ew.rowbuf.size();
  // (A padded row is read in place: its entries beyond |S| are zero.)
  const double* fb = f;
  if (!padded) {
    std::copy_n(f, d, ew.rowbuf.data());
    fb = ew.rowbuf.data();
  }
  batch ax(0.0), ay(0.0);
  auto bad = batch(0.0) != batch(0.0);
  for (size_t k = 0; k < dp; k += B) {
    const batch fv = batch::load_unaligned(fb + k), x = batch::load_unaligned(cx + k), y = batch::load_unaligned(cy + k);
    const auto pos = fv > batch(0.0);
    // The logarithm in registers (xsimd): through a buffer, the log's
    // stores and these loads stalled on store forwarding (perf).
    const batch l = xsimd::select(pos, xsimd::log(fv), batch(0.0));
    ax = xsimd::fma(x, l, ax);
    ay = xsimd::fma(y, l, ay);
    bad = bad || ((x != batch(0.0) || y != batch(0.0)) && !pos);
  }
  if (xsimd::any(bad)) return false;
  gx = xsimd::hadd(ax);
  gy = xsimd::hadd(ay);
  return true;
}
}  // namespace

// Pass 1 for one patch vertex p (vertex j = patch[p]; is_center: j is the
// center, is_source: j is one of the sources) from its heat row f,
// f[k] = (h_k)_j: the estimated gradient (ew.grad[2p], [2p + 1]) and what it
// may be used for (ew.use[p]). Vertices inside the two-ring stencil use the
// one-ring estimator: the heat from them peaks inside the stencil, where no
// quadratic fits it. Callers may visit the patch in any order (the localized
// query walks the solver's rows in memory order).
void HeatLogMap::vertex_gradient(size_t p, bool is_center, bool is_source, const double* f, bool padded,
                                 double h_center, const LogMapEstimator& est, LogMapStats& st,
                                 LogMapEstimatorWorkspace& ew, LogMapPathWorkspace& pw) const {
  const size_t d = ew.sources.size();
  const bool use_log = est.angle != LogMapAngle::HeatAverage;
  double gx = 0, gy = 0;
  bool plain = !use_log;
  if (!is_center) {
    if (use_log) {
      const bool wide_stencil = !ew.coef2.empty() && !is_source;
      const size_t dp = ew.rowbuf.size();
      const double* cx = ew.cpad.data() + (wide_stencil ? 2 * dp : 0);
      if (!log_gradient(f, padded, cx, cx + dp, ew, gx, gy)) {
        plain = true;
        ++st.angle_fallbacks;
      }
    }
    if (plain)
      for (size_t k = 0; k < d; ++k) {
        gx += ew.coef1[2 * k] * f[k];
        gy += ew.coef1[2 * k + 1] * f[k];
      }
  }
  ew.grad[2 * p] = gx;
  ew.grad[2 * p + 1] = gy;
  // Path correction: the radius from the center's heat (lane 0), sqrt(t) log(h_i(i) / h_i(j)),
  // which grows like the distance; unlike the Poisson distance it is the same
  // for the localized and the full solve (the localized map must equal the full one).
  if (est.lattice == LatticeCorrection::Path && use_log)
    pw.r[p] = f[0] > 0 && h_center > 0 ? std::sqrt(geo_.time()) * std::log(h_center / f[0])
                                       : std::numeric_limits<double>::infinity();
  ew.use[p] = plain || is_center ? GradientUse::Plain
                                 : (f[0] < kNearFieldHeat * h_center ? GradientUse::FarField : GradientUse::NearField);
}

}  // namespace locus
