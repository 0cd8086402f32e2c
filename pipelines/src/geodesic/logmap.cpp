// Smoothed log map by heat diffusion (pipelines/include/locus/pipelines/geodesic/logmap.hpp; thesis §6.5-6.6;
// measurements behind the choices here: docs/logmap.md).
#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/core/host_allocator.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <utility>
#include <limits>
#include <numbers>
#include <string>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_wide.hpp"
#include "locus/kernels/simd/log_array.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include <xsimd/xsimd.hpp>
#include "locus/error.hpp"

namespace locus {

namespace {

inline double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void check_outputs(const LogMapOutput& out, size_t np) {
  if (out.distance.size() != np || out.angle.size() != np || out.u.size() != np || out.v.size() != np)
    fail(ErrorCode::BadUsage, "log map: every output span needs one entry per patch vertex (" + std::to_string(np) + ")");
}

// A vertex in another component than the center has no geodesic path to it
// and receives no heat from it: no distance, no direction. Refused rather than
// mapped to infinity or NaN. Patch ids are already checked to be in range.
void check_same_component(const HeatGeodesic& geo, int32_t center, std::span<const int32_t> patch) {
  if (geo.num_components() <= 1) return;
  const int32_t c = geo.component(center);
  for (size_t k = 0; k < patch.size(); ++k)
    if (geo.component(patch[k]) != c)
      fail(ErrorCode::BadUsage, "log map: patch entry " + std::to_string(k) + " is vertex " + std::to_string(patch[k]) +
                                    ", in another connected component than the center " + std::to_string(center));
}

}  // namespace

HeatLogMap::HeatLogMap(const Mesh& m, const LogMapOptions& opt, const RunContext& ctx, const MeshDerived* derived)
    : opt_(opt), geo_(m, opt.geodesic, ctx, derived), x_(m.x), y_(m.y), z_(m.z) {
  prepare(m, derived);
}

HeatLogMap::HeatLogMap(const Mesh& m, const LogMapOptions& opt, HeatGeodesicFactors factors)
    : opt_(opt), geo_(m, opt.geodesic, std::move(factors)), x_(m.x), y_(m.y), z_(m.z) {
  prepare(m);
}

void HeatLogMap::prepare(const Mesh& m, const MeshDerived* derived) {
  const int32_t n = m.num_vertices();
  // Eq. 6.2: the mean-curvature normal where it is meaningful, the area normal
  // where it vanishes (planar regions) and at boundary vertices (where L_C p has
  // an in-plane boundary term). Oriented to the side of the face normals so that
  // the map keeps the faces' orientation.
  EdgeIncidence own;
  if (!derived) own = edge_incidence(m);
  const EdgeIncidence& inc = derived ? derived->incidence : own;
  const HostVector<double> hn = mean_curvature_normals(m, &inc);
  const HostVector<double> an = area_weighted_normals(m);
  const Edges& e = inc.edges;
  HostVector<uint8_t>& boundary = boundary_;
  boundary.assign(static_cast<size_t>(n), 0);
  for (size_t k = 0; k < e.e0.size(); ++k)
    if (e.face_count[k] == 1) boundary[e.e0[k]] = boundary[e.e1[k]] = 1;
  // |H n| below 1e-8 / h means a curvature radius above 1e8 h: numerically planar.
  const double tiny = 1e-8 / geo_.mean_edge_length();
  normal_.resize(3 * static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) {
    const double* h = hn.data() + 3 * static_cast<size_t>(i);
    const double* a = an.data() + 3 * static_cast<size_t>(i);
    const double len = std::sqrt(dot3(h, h));
    double* o = normal_.data() + 3 * static_cast<size_t>(i);
    if (!boundary[i] && len > tiny && std::isfinite(len)) {
      const double s = dot3(h, a) < 0 ? -1.0 / len : 1.0 / len;
      for (int c = 0; c < 3; ++c) o[c] = h[c] * s;
    } else {
      for (int c = 0; c < 3; ++c) o[c] = a[c];
    }
  }
}

void HeatLogMap::frame(int32_t i, double n[3], double e1[3], double e2[3]) const {
  const TriangleGradients& g = geo_.gradients();
  for (int c = 0; c < 3; ++c) n[c] = normal_[3 * static_cast<size_t>(i) + c];
  // Lowest-numbered neighbor: deterministic, independent of face order.
  int32_t ref = -1;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q)
    for (int s = 0; s < 3; ++s) {
      const int32_t w = g.tri[3 * static_cast<int64_t>(g.vf_faces[q]) + s];
      if (w != i && (ref < 0 || w < ref)) ref = w;
    }
  double d[3] = {x_[ref] - x_[i], y_[ref] - y_[i], z_[ref] - z_[i]};
  const double dn = dot3(d, n);
  for (int c = 0; c < 3; ++c) d[c] -= dn * n[c];
  const double len = std::sqrt(dot3(d, d));
  for (int c = 0; c < 3; ++c) e1[c] = d[c] / len;
  e2[0] = n[1] * e1[2] - n[2] * e1[1];
  e2[1] = n[2] * e1[0] - n[0] * e1[2];
  e2[2] = n[0] * e1[1] - n[1] * e1[0];
}

// A star is irregular when a corner angle at i is off the regular value 2 pi / valence
// by more than 25 % or its longest edge exceeds 1.6 times its shortest. Icospheres
// of any level stay well inside (angles within ~15 %, edge ratio < 1.3); convex
// hulls of random points mostly do not.
bool HeatLogMap::irregular_star(int32_t i) const {
  const TriangleGradients& g = geo_.gradients();
  const int64_t valence = g.vf_offsets[i + 1] - g.vf_offsets[i];
  if (valence < 3) return false;
  double total = 0, lmin = std::numeric_limits<double>::infinity(), lmax = 0;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
    const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(g.vf_faces[q]);
    const int s = t[0] == i ? 0 : (t[1] == i ? 1 : 2);
    const int32_t a = t[(s + 1) % 3], b = t[(s + 2) % 3];
    const double u[3] = {x_[a] - x_[i], y_[a] - y_[i], z_[a] - z_[i]};
    const double w[3] = {x_[b] - x_[i], y_[b] - y_[i], z_[b] - z_[i]};
    const double lu = std::sqrt(dot3(u, u)), lw = std::sqrt(dot3(w, w));
    lmin = std::min({lmin, lu, lw});
    lmax = std::max({lmax, lu, lw});
    const double ang = std::acos(std::clamp(dot3(u, w) / (lu * lw), -1.0, 1.0));
    total += ang;
  }
  const double regular = total / static_cast<double>(valence);
  double worst = 0;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
    const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(g.vf_faces[q]);
    const int s = t[0] == i ? 0 : (t[1] == i ? 1 : 2);
    const int32_t a = t[(s + 1) % 3], b = t[(s + 2) % 3];
    const double u[3] = {x_[a] - x_[i], y_[a] - y_[i], z_[a] - z_[i]};
    const double w[3] = {x_[b] - x_[i], y_[b] - y_[i], z_[b] - z_[i]};
    const double ang = std::acos(std::clamp(dot3(u, w) / std::sqrt(dot3(u, u) * dot3(w, w)), -1.0, 1.0));
    worst = std::max(worst, std::abs(ang - regular) / regular);
  }
  return worst > 0.25 || lmax > 1.6 * lmin;
}

// A lattice defect: an interior vertex whose valence is not the triangle
// lattice's 6 (an icosphere's 12 corners: valence 5, a cone of the lattice;
// such stars may still be regular in shape). The lattice corrections model
// the heat's anisotropy along straight rays through a lattice; around a cone
// the rays bend and the correction made things worse (icosphere 7, vertex 0:
// Path 4.35e-3 against 3.19e-3 uncorrected at t = h^2, 1.22e-3 against 0.95e-3
// at 4 h^2; also without the center's own star in the Path sums:
// docs/logmap.md, "Defect centers"), so they apply at valence-6 stars only.
bool HeatLogMap::defect_star(int32_t i) const {
  const TriangleGradients& g = geo_.gradients();
  return g.vf_offsets[i + 1] - g.vf_offsets[i] != 6 && !boundary_[i];
}

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
  HostVector<int32_t>& S = ws.sources;
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
    HostVector<int32_t>& R2 = ws.ring2;
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
  ws.coef1.assign(2 * d, 0.0);
  double star_area = 0;
  for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
    const int32_t f = g.vf_faces[q];
    star_area += g.area[f];
    const double* b = g.basis.data() + 9 * static_cast<int64_t>(f);
    for (int s = 0; s < 3; ++s) {
      const int32_t w = g.tri[3 * static_cast<int64_t>(f) + s];
      const size_t k = static_cast<size_t>(std::find(S.begin(), S.begin() + ring1, w) - S.begin());
      // P grad(phi) . e = grad(phi) . e for e in the tangent plane.
      ws.coef1[2 * k] += g.area[f] * dot3(b + 3 * s, e1);
      ws.coef1[2 * k + 1] += g.area[f] * dot3(b + 3 * s, e2);
    }
  }
  // Divided by the star's area: the average gradient itself (eq. 6.8 up to a
  // positive factor, same angle), whose magnitude the lattice correction needs.
  for (double& c : ws.coef1) c /= star_area;
  ws.lattice.clear();
  if (angle != LogMapAngle::HeatAverage && est.lattice != LatticeCorrection::None)
    prepare_lattice(e1, e2, est.lattice, ring1, ws);
  ws.coef2.clear();
  if (angle == LogMapAngle::LogHeatTwoRing) two_ring_coefficients(i, e1, e2, ws);
  return est;
}

// LogHeatTwoRing: ws.coef2, the gradient at i of the least-squares quadratic
// through the values at the sources (i, its ring, its two-ring) in the
// tangent-plane frame (e1, e2); left empty for a degenerate stencil.
void HeatLogMap::two_ring_coefficients(int32_t i, const double e1[3], const double e2[3], LogMapWorkspace& ws) const {
  const HostVector<int32_t>& S = ws.sources;
  const size_t d = S.size();
  // Normal equations of the quadratic fit in coordinates scaled by 1/h, solved
  // by a 6x6 Cholesky factorization (SPD unless the stencil is degenerate).
  const double inv_h = 1.0 / geo_.mean_edge_length();
  double N[6][6] = {};
  ws.phi.resize(6 * d);
  for (size_t k = 0; k < d; ++k) {
    const int32_t v = S[k];
    const double p[3] = {x_[v] - x_[i], y_[v] - y_[i], z_[v] - z_[i]};
    const double qx = dot3(p, e1) * inv_h, qy = dot3(p, e2) * inv_h;
    double* f = ws.phi.data() + 6 * k;
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
  if (!(dmin > 1e-12 * dmax)) return;
  ws.coef2.resize(2 * d);
  for (size_t k = 0; k < d; ++k) {
    double y[6];
    const double* f = ws.phi.data() + 6 * k;
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
    ws.coef2[2 * k] = y[1] * inv_h;
    ws.coef2[2 * k + 1] = y[2] * inv_h;
  }
}

// Lattice (dispersion) correction. Far from its source j the discrete heat
// h_j = A^{-1} e_j behaves locally like a plane wave exp(k . x), and at vertex v
// (A exp(k . x))_v = 0 gives the dispersion relation
//     Phi(k) = sum_u w_vu (exp(k . e_vu) - 1) = m_v / t
// (w the cotan weights, e_vu the star's edges in the tangent plane, m_v the
// lumped mass). Its solution set bounds the convex set K = {Phi <= m/t}, and
// h_j ~ exp(-F(x - x_j)) with F(y) = max_{k in K} k . y (large deviations of
// the lattice walk): an anisotropic (Finsler) distance whose unit ball is
// polar to K. At t = h^2 the star spans about one decay length, so K is
// visibly not a disk on a sheared or irregular star, and the gradient of
// log h_j at i (= -k*, the maximizer) is not parallel to the direction y of j;
// y is the normal of the boundary of K at k*, grad Phi(k*). So for the observed
// direction psi of grad log h_j we take rho(psi) on the boundary
// (Phi(-rho u(psi)) = m/t, Newton) and the direction to j
// -grad Phi(-rho u) = -sum w e exp(-rho u . e), tabulated per center as an
// offset delta(psi) at kLatticeTable angles and interpolated linearly.
// Star: v = i only; Ring: Phi and m summed over i and its one ring, all edges
// written in i's frame (the average lattice around i).
namespace {
constexpr int kLatticeTable = 128;

// The table's offset at angle th: periodic over [0, 2 pi), linear interpolation.
double lattice_offset(const double* table, double th) {
  const double pos = (th < 0 ? th + 2 * std::numbers::pi : th) * (kLatticeTable / (2 * std::numbers::pi));
  const int a0 = std::min(kLatticeTable - 1, static_cast<int>(pos));
  const double w = pos - a0;
  return (1 - w) * table[a0] + w * table[(a0 + 1) % kLatticeTable];
}

// Newton for the dispersion set's radius rho > 0 in one direction, shared by the
// star/ring table (exponential sums) and the Path table (Taylor moments):
// eval(rho) gives (f, f') with f' > 0 on a convex set. False when it leaves that
// regime (the caller then applies no correction); rho holds the last iterate.
template <class Eval>
bool newton_dispersion_radius(double& rho, double tol, Eval eval) {
  for (int it = 0; it < 60; ++it) {
    const auto [f, df] = eval(rho);
    if (!(df > 0) || !std::isfinite(f)) return false;
    const double step = f / df;
    rho -= step;
    if (!(rho > 0)) return false;
    if (std::abs(step) <= tol * rho) return true;
  }
  return false;
}
}

void HeatLogMap::prepare_lattice(const double e1[3], const double e2[3], LatticeCorrection lattice, size_t ring1,
                                 LogMapWorkspace& ws) const {
  const TriangleGradients& g = geo_.gradients();
  HostVector<double>& st = ws.star;
  st.clear();
  double mass = 0;
  // ws.sources starts with i and its one ring (ring1 entries), then maybe the two-ring.
  const size_t stars = lattice == LatticeCorrection::Ring ? ring1 : 1;
  HostVector<int32_t>& ends = ws.star_ends;
  for (size_t r = 0; r < stars; ++r) {
    const int32_t v = ws.sources[r];
    const size_t first = st.size() / 3;  // v's entries start here; one per neighbor u
    ends.clear();
    for (int64_t q = g.vf_offsets[v]; q < g.vf_offsets[v + 1]; ++q) {
      const int32_t f = g.vf_faces[q];
      const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(f);
      const int s = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
      const int32_t a = t[(s + 1) % 3], b = t[(s + 2) % 3];
      mass += g.area[f] / 3;
      const double pa[3] = {x_[a] - x_[v], y_[a] - y_[v], z_[a] - z_[v]};
      const double pb[3] = {x_[b] - x_[v], y_[b] - y_[v], z_[b] - z_[v]};
      const double twice = 2 * g.area[f];
      // Edge (v, a) gets half the cotangent at b, edge (v, b) half the one at a:
      // cot b = (v - b) . (a - b) / 2A, cot a = (v - a) . (b - a) / 2A.
      const double* edges[2] = {pa, pb};
      const int32_t ends_of[2] = {a, b};
      const double w[2] = {0.5 * (dot3(pb, pb) - dot3(pa, pb)) / twice, 0.5 * (dot3(pa, pa) - dot3(pa, pb)) / twice};
      for (int k = 0; k < 2; ++k) {
        // Each interior edge (v, u) is met from two faces: one entry, weights summed.
        const size_t seen = static_cast<size_t>(std::find(ends.begin(), ends.end(), ends_of[k]) - ends.begin());
        if (seen < ends.size()) {
          st[3 * (first + seen) + 2] += w[k];
          continue;
        }
        ends.push_back(ends_of[k]);
        const double* e = edges[k];
        double ex = dot3(e, e1), ey = dot3(e, e2);
        const double l2 = ex * ex + ey * ey;
        if (l2 > 0) {  // projected, rescaled to the edge's length (normal coordinates)
          const double sc = std::sqrt(dot3(e, e) / l2);
          ex *= sc;
          ey *= sc;
        }
        st.push_back(ex);
        st.push_back(ey);
        st.push_back(w[k]);
      }
    }
  }
  const double target = mass / geo_.time();
  const size_t ne = st.size() / 3;
  ws.lattice.resize(kLatticeTable);
  double rho = 1.0 / std::sqrt(geo_.time());
  for (int a = 0; a < kLatticeTable; ++a) {
    const double psi = 2 * std::numbers::pi * a / kLatticeTable;
    const double ux = std::cos(psi), uy = std::sin(psi);
    const bool ok = newton_dispersion_radius(rho, 1e-13, [&](double r) {
      double f = -target, df = 0;
      for (size_t e = 0; e < ne; ++e) {
        const double c = ux * st[3 * e] + uy * st[3 * e + 1];
        const double x = std::exp(-r * c);
        f += st[3 * e + 2] * (x - 1);
        df -= st[3 * e + 2] * c * x;
      }
      return std::pair{f, df};
    });
    if (!ok) {  // not a convex dispersion set (e.g. negative weights): no correction
      ws.lattice.clear();
      return;
    }
    double gx = 0, gy = 0;
    for (size_t e = 0; e < ne; ++e) {
      const double c = ux * st[3 * e] + uy * st[3 * e + 1];
      const double x = st[3 * e + 2] * std::exp(-rho * c);
      gx -= x * st[3 * e];
      gy -= x * st[3 * e + 1];
    }
    ws.lattice[a] = std::remainder(std::atan2(gy, gx) - psi, 2 * std::numbers::pi);
    if (!(std::abs(ws.lattice[a]) < 0.5)) {
      ws.lattice.clear();
      return;
    }
  }
}

// Pass 1 for one patch vertex p (vertex j = patch[p]; is_center: j is the
// center, is_source: j is one of the sources) from its heat row f,
// f[k] = (h_k)_j: the estimated gradient (ws.grad[3p], [3p + 1]) and whether
// it is one of log h (ws.grad[3p + 2]; 0 for the center and for HeatAverage
// fallbacks: no recenter, no correction). Vertices inside the two-ring stencil
// use the one-ring estimator: the heat from them peaks inside the stencil,
// where no quadratic fits it. Callers may visit the patch in any order (the
// localized query walks the solver's rows in memory order).
void HeatLogMap::vertex_gradient(size_t p, bool is_center, bool is_source, const double* f, bool padded,
                                 double h_center, const LogMapEstimator& est, LogMapStats& st,
                                 LogMapWorkspace& ws) const {
  const size_t d = ws.sources.size();
  const bool use_log = est.angle != LogMapAngle::HeatAverage;
  double gx = 0, gy = 0;
  bool plain = !use_log;
  if (!is_center) {
    const bool wide_stencil = !ws.coef2.empty() && !is_source;
    if (use_log) {
      // Padded to whole SIMD batches (zero heat and zero coefficients beyond |S|),
      // logs in bulk, then both components in vector accumulators; a used source
      // (non-zero coefficient) with non-positive heat sends the vertex to the
      // HeatAverage fallback.
      using batch = xsimd::batch<double>;
      constexpr size_t B = batch::size;
      const size_t dp = ws.logrow.size();
      // (A padded row is read in place: its entries beyond |S| are zero.)
      const double* fb = f;
      if (!padded) {
        std::copy_n(f, d, ws.rowbuf.data());
        fb = ws.rowbuf.data();
      }
      const double* cx = ws.cpad.data() + (wide_stencil ? 2 * dp : 0);
      const double* cy = cx + dp;
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
      if (xsimd::any(bad)) {
        plain = true;
        ++st.angle_fallbacks;
      } else {
        gx = xsimd::hadd(ax);
        gy = xsimd::hadd(ay);
      }
    }
    if (plain)
      for (size_t k = 0; k < d; ++k) {
        gx += ws.coef1[2 * k] * f[k];
        gy += ws.coef1[2 * k + 1] * f[k];
      }
  }
  ws.grad[3 * p] = gx;
  ws.grad[3 * p + 1] = gy;
  // Path correction: the radius from the center's heat (lane 0), sqrt(t) log(h_i(i) / h_i(j)),
  // which grows like the distance; unlike the Poisson distance it is the same
  // for the localized and the full solve (the localized map must equal the full one).
  if (est.lattice == LatticeCorrection::Path && use_log)
    ws.path_r[p] = f[0] > 0 && h_center > 0 ? std::sqrt(geo_.time()) * std::log(h_center / f[0])
                                            : std::numeric_limits<double>::infinity();
  // 1: usable for the corrections; 2: also beyond the near field (for recenter).
  // The near field is told by the heat from the center (e^-4 of its peak, about
  // 4 edges at t = h^2), not by the distance: the localized and the full map
  // must see the same set.
  ws.grad[3 * p + 2] = plain || is_center ? 0.0 : (f[0] < 0.0183 * h_center ? 2.0 : 1.0);
}

void HeatLogMap::begin_gradients(size_t patch_size, LogMapWorkspace& ws) const {
  ws.sorted_sources.assign(ws.sources.begin(), ws.sources.end());
  std::sort(ws.sorted_sources.begin(), ws.sorted_sources.end());
  // Padded row buffers and de-interleaved coefficients (one-ring, then two-ring
  // or the one-ring again) for vertex_gradient's vector loop.
  const size_t d = ws.sources.size(), B = xsimd::batch<double>::size, dp = (d + B - 1) / B * B;
  ws.logrow.assign(dp, 0.0);
  ws.rowbuf.assign(dp, 0.0);
  ws.cpad.assign(4 * dp, 0.0);
  for (size_t k = 0; k < d; ++k) {
    const HostVector<double>& c2 = ws.coef2.empty() ? ws.coef1 : ws.coef2;
    ws.cpad[k] = ws.coef1[2 * k];
    ws.cpad[dp + k] = ws.coef1[2 * k + 1];
    ws.cpad[2 * dp + k] = c2[2 * k];
    ws.cpad[3 * dp + k] = c2[2 * k + 1];
  }
  ws.grad.resize(3 * patch_size);
  ws.path_r.resize(patch_size);
}

// Path correction (LatticeCorrection::Path, the default at regular stars). First-order picture:
// far from j, log h_j ~ -D(x, j) with D the lattice's Finsler distance, whose
// unit ball varies with position; along the ray from i to j,
// grad_x D(i, j) is (to first order) the dual direction of the Finsler norm
// averaged over the ray, plus a transverse term from the norm's variation. This
// takes the first part: per sector of the first-pass map (kPathSectors, with
// its two neighbors) and per radius R (kPathBins up to the patch's largest
// distance), the dispersion relations of the stars of the patch vertices in
// the sector with r < R, summed with weight mass / r (uniform per unit length),
// plus the center's star; each star's edges turned into i's tangent plane by
// the minimal rotation of its normal onto n_i, projected and rescaled to their
// length. The offset at a vertex interpolates linearly in sector and radius,
// from the center's own offset at r = 0.
namespace {
constexpr int kPathSectors = 64, kPathBins = 6, kPathDegree = 10;
// Edge moments per (sector, radius) cell: monomials of degree 0..kPathDegree,
// x^a y^(d - a) at path_monomial(d, a), then the cell's weighted mass.
constexpr int kPathMonomials = (kPathDegree + 1) * (kPathDegree + 2) / 2;
constexpr int path_monomial(int d, int a) { return d * (d + 1) / 2 + a; }

// Adds sum w x^a y^(d - a) over the edges (x, y, w) of exyw to
// cell[path_monomial(d, a)], degrees 1..kPathDegree.
void add_edge_moments(const HostVector<double>& exyw, double* cell) {
  constexpr int D = kPathDegree;
  double px[D + 1], py[D + 1];
  for (size_t e = 0; e < exyw.size() / 3; ++e) {
    // py stored reversed (py[D - k] = y^k): one degree's monomials are a contiguous product.
    px[0] = exyw[3 * e + 2];  // px[a] = w x^a
    py[D] = 1;
    for (int d = 1; d <= D; ++d) px[d] = px[d - 1] * exyw[3 * e], py[D - d] = py[D - d + 1] * exyw[3 * e + 1];
    for (int d = 1; d <= D; ++d) {
      double* out = cell + path_monomial(d, 0);
      const double* yr = py + D - d;  // yr[a] = y^(d - a)
      for (int a2 = 0; a2 <= d; ++a2) out[a2] += px[a2] * yr[a2];
    }
  }
}

// Binomial coefficients and factorials up to kPathDegree (exact in double).
// Compile-time constants: the compiler folds them into the sums below (a
// division by 0! = 1! = 1 disappears and its product may fuse into an FMA),
// as it did when they were computed inside one function; the same folding
// keeps the results bit-identical to that version.
struct PathTaylorTables {
  double binom[kPathDegree + 1][kPathDegree + 1] = {};
  double fact[kPathDegree + 1] = {};
  constexpr PathTaylorTables() {
    constexpr int D = kPathDegree;
    for (int d = 0; d <= D; ++d) {
      binom[d][0] = 1;
      for (int a = 1; a <= d; ++a) binom[d][a] = binom[d - 1][a - 1] + (a < d ? binom[d - 1][a] : 0);
    }
    fact[0] = 1;
    for (int d = 1; d <= D; ++d) fact[d] = fact[d - 1] * d;
  }
};

// The Path table of one sector: for radius bins 0..kPathBins, the cumulative
// sum of its and its two neighbors' cells of `mom` (from the center's cell at
// bin 0), the dispersion set's radius in the sector's direction (Newton on the
// Taylor series through the moments) and the offset of the direction to j,
// into out[0..kPathBins] (0 where Newton fails or the offset is not small).
constexpr PathTaylorTables kPathTaylor;

void path_sector_offsets(int sct, const double* mom, double h, double tt, double* out) {
  constexpr int D = kPathDegree, NM = kPathMonomials;
  constexpr const PathTaylorTables& tb = kPathTaylor;
  const double dtheta = 2 * std::numbers::pi / kPathSectors;
  const double* center_cell = mom + static_cast<size_t>(kPathSectors) * kPathBins * (NM + 1);
  const double psi = (sct + 0.5) * dtheta, ux = std::cos(psi), uy = std::sin(psi);
  double pux[D + 1], puy[D + 1];
  pux[0] = puy[0] = 1;
  for (int d = 1; d <= D; ++d) pux[d] = pux[d - 1] * ux, puy[d] = puy[d - 1] * uy;
  double acc[NM + 1];
  std::copy_n(center_cell, NM + 1, acc);
  double rho = h / std::sqrt(tt);  // scaled: rho h
  for (int b = 0; b <= kPathBins; ++b) {
    if (b > 0)
      for (int ds = -1; ds <= 1; ++ds) {
        const double* cl =
            mom + (static_cast<size_t>((sct + ds + kPathSectors) % kPathSectors) * kPathBins + b - 1) * (NM + 1);
        for (int m = 0; m <= NM; ++m) acc[m] += cl[m];
      }
    // P[d] = sum w (u.e)^d; Gx[d], Gy[d] = sum w e_x (u.e)^d, sum w e_y (u.e)^d.
    double P[D + 1] = {}, Gx[D] = {}, Gy[D] = {};
    for (int d = 1; d <= D; ++d)
      for (int a = 0; a <= d; ++a) P[d] += tb.binom[d][a] * pux[a] * puy[d - a] * acc[path_monomial(d, a)];
    for (int d = 0; d < D; ++d)
      for (int a = 0; a <= d; ++a) {
        const double cu = tb.binom[d][a] * pux[a] * puy[d - a];
        Gx[d] += cu * acc[path_monomial(d + 1, a + 1)];
        Gy[d] += cu * acc[path_monomial(d + 1, a)];
      }
    // Phi(-rho u) = sum_d (-rho)^d P[d] / d! = mass / t (Newton in rho).
    const double target = acc[NM] / tt;
    const bool ok = newton_dispersion_radius(rho, 1e-12, [&](double r) {
      double f = -target, df = 0, pw = 1;  // pw = (-r)^(d-1)
      for (int d = 1; d <= D; ++d) {
        df -= d * pw * P[d] / tb.fact[d];
        pw *= -r;
        f += pw * P[d] / tb.fact[d];
      }
      return std::pair{f, df};
    });
    double off = 0;
    if (ok) {
      double gx = 0, gy = 0, pw = 1;
      for (int d = 0; d < D; ++d) {
        gx -= pw * Gx[d] / tb.fact[d];
        gy -= pw * Gy[d] / tb.fact[d];
        pw *= -rho;
      }
      off = std::remainder(std::atan2(gy, gx) - psi, 2 * std::numbers::pi);
      if (!(std::abs(off) < 0.5)) off = 0;
    }
    out[b] = off;
  }
}
}  // namespace

double HeatLogMap::path_offset_at(const HostVector<double>& table, double th, double r, double rmax) {
  const double pos = (th < 0 ? th + 2 * std::numbers::pi : th) * (kPathSectors / (2 * std::numbers::pi)) - 0.5;
  const double fl = std::floor(pos);
  const int s0 = (static_cast<int>(fl) % kPathSectors + kPathSectors) % kPathSectors, s1 = (s0 + 1) % kPathSectors;
  const double ws = pos - fl;
  const double rb = std::clamp(r / rmax * kPathBins, 0.0, static_cast<double>(kPathBins));
  const int b0 = std::min(kPathBins - 1, static_cast<int>(rb));
  const double wb = rb - b0;
  // table: (kPathBins + 1) radii per sector, radius 0 = the center's star.
  auto at = [&](int s, int b) { return table[static_cast<size_t>(s) * (kPathBins + 1) + b]; };
  const double o0 = (1 - wb) * at(s0, b0) + wb * at(s0, b0 + 1), o1 = (1 - wb) * at(s1, b0) + wb * at(s1, b0 + 1);
  return (1 - ws) * o0 + ws * o1;
}

// One star's dispersion relation for the Path table: the edges of v's star
// (interior edges met from two faces once, weights summed) turned into i's
// tangent plane (normal n, frame e1, e2) by the minimal rotation of v's normal
// onto n, projected and rescaled to their length, in units of h (inv_h = 1 / h);
// their moments, times `weight`, go to `cell`, weight * v's lumped mass to its
// last entry.
void HeatLogMap::add_path_star(int32_t v, double weight, const double n[3], const double e1[3], const double e2[3],
                               double inv_h, double* cell, LogMapWorkspace& ws) const {
  const TriangleGradients& g = geo_.gradients();
  const double* nv = normal_.data() + 3 * static_cast<size_t>(v);
  const double c[3] = {nv[1] * n[2] - nv[2] * n[1], nv[2] * n[0] - nv[0] * n[2], nv[0] * n[1] - nv[1] * n[0]};
  const double cosa = dot3(nv, n);
  const double k = cosa > -0.9 ? 1 / (1 + cosa) : 0.0;
  HostVector<int32_t>& ends = ws.star_ends;
  HostVector<double>& exyw = ws.star;  // (x, y, weight) per edge
  ends.clear();
  exyw.clear();
  for (int64_t q = g.vf_offsets[v]; q < g.vf_offsets[v + 1]; ++q) {
    const int32_t f = g.vf_faces[q];
    const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(f);
    const int s = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    const int32_t a = t[(s + 1) % 3], b = t[(s + 2) % 3];
    cell[kPathMonomials] += weight * g.area[f] / 3;
    const double pa[3] = {x_[a] - x_[v], y_[a] - y_[v], z_[a] - z_[v]};
    const double pb[3] = {x_[b] - x_[v], y_[b] - y_[v], z_[b] - z_[v]};
    const double twice = 2 * g.area[f];
    // Edge (v, a) gets half the cotangent at b, edge (v, b) half the one at a.
    const double w[2] = {0.5 * (dot3(pb, pb) - dot3(pa, pb)) / twice, 0.5 * (dot3(pa, pa) - dot3(pa, pb)) / twice};
    const double* edges[2] = {pa, pb};
    const int32_t ends_of[2] = {a, b};
    for (int e = 0; e < 2; ++e) {
      const size_t seen = static_cast<size_t>(std::find(ends.begin(), ends.end(), ends_of[e]) - ends.begin());
      if (seen < ends.size()) {
        exyw[3 * seen + 2] += weight * w[e];
        continue;
      }
      const double* x = edges[e];
      // R x = x + c x x + c x (c x x) / (1 + cos): the minimal rotation taking n_v to n_i.
      const double cx[3] = {c[1] * x[2] - c[2] * x[1], c[2] * x[0] - c[0] * x[2], c[0] * x[1] - c[1] * x[0]};
      const double ccx[3] = {c[1] * cx[2] - c[2] * cx[1], c[2] * cx[0] - c[0] * cx[2], c[0] * cx[1] - c[1] * cx[0]};
      const double rx[3] = {x[0] + cx[0] + k * ccx[0], x[1] + cx[1] + k * ccx[1], x[2] + cx[2] + k * ccx[2]};
      double ex = dot3(rx, e1), ey = dot3(rx, e2);
      const double l2 = ex * ex + ey * ey;
      if (l2 > 0) {  // projected, rescaled to the edge's length
        const double sc = std::sqrt(dot3(x, x) / l2) * inv_h;
        ex *= sc;
        ey *= sc;
      }
      ends.push_back(ends_of[e]);
      exyw.push_back(ex);
      exyw.push_back(ey);
      exyw.push_back(weight * w[e]);
    }
  }
  add_edge_moments(exyw, cell);
}

// Phi(k) = sum w (exp(k.e) - 1) and its gradient, summed over many stars,
// through the moments M[d][a] = sum w x^a y^(d-a) of the edges (x, y) = e / h,
// degrees 1..kPathDegree (Taylor series of exp; |k.e| <~ 1.5 at t = h^2, so the
// remainder is below 1.5^11 / 11! ~ 2e-6 of the sum; same E_a as the direct
// sums to 4 digits, docs/logmap.md): one pass over each star, and every
// (sector, radius) sum is a sum of a few cells' moments.
void HeatLogMap::path_offsets(std::span<const int32_t> patch, LogMapWorkspace& ws) const {
  const int32_t i = ws.sources[0];
  double n[3], e1[3], e2[3];
  frame(i, n, e1, e2);
  const HostVector<double>& radius = ws.path_r;
  double rmax = 0;
  for (size_t p = 0; p < patch.size(); ++p)
    if (std::isfinite(radius[p])) rmax = std::max(rmax, radius[p]);
  ws.path_rmax = rmax > 0 ? rmax : 1.0;
  const double h = geo_.mean_edge_length(), inv_h = 1 / h, dtheta = 2 * std::numbers::pi / kPathSectors;
  constexpr int NM = kPathMonomials;
  const size_t cells = static_cast<size_t>(kPathSectors) * kPathBins;
  HostVector<double>& mom = ws.path_moments;
  mom.assign((cells + 1) * (NM + 1), 0.0);  // per cell: NM moments, then the weighted mass; last: the center
  // The center's star (weight: the length h it stands for), then each patch
  // vertex in its cell, weight ~ 1 / (r * 3 sectors' angle): uniform per unit
  // length along the ray.
  add_path_star(i, h, n, e1, e2, inv_h, mom.data() + cells * (NM + 1), ws);
  for (size_t p = 0; p < patch.size(); ++p) {
    if (patch[p] == i || !std::isfinite(radius[p])) continue;
    const double r = radius[p], th = ws.path_angle[p];
    const int sct = static_cast<int>(std::floor((th < 0 ? th + 2 * std::numbers::pi : th) / dtheta)) % kPathSectors;
    const int b = std::min(kPathBins - 1, static_cast<int>(r / ws.path_rmax * kPathBins));
    add_path_star(patch[p], 1.0 / (std::max(r, h) * 3 * dtheta), n, e1, e2, inv_h,
                  mom.data() + (static_cast<size_t>(sct) * kPathBins + b) * (NM + 1), ws);
  }
  // Per sector: the cumulative sum over radius bins of its and its neighbors' cells.
  ws.path.assign(static_cast<size_t>(kPathSectors) * (kPathBins + 1), 0.0);
  for (int sct = 0; sct < kPathSectors; ++sct)
    path_sector_offsets(sct, mom.data(), h, geo_.time(), ws.path.data() + static_cast<size_t>(sct) * (kPathBins + 1));
}

namespace {
// Recenter: far from the stencil, grad log h_j at i is k*(direction of j) plus
// a part b that does not depend on j (the heat kernel's vertex-level factors
// around i on irregular meshes). The k* lie on a closed convex curve around
// 0, centrally symmetric for a symmetric operator; a least-squares circle
// through the gradients (Kasa: |g|^2 = 2 b.g + c) estimates b. Only with
// directions all around the center (resultant of the unit directions < 0.25)
// and beyond the near field (ws.grad[3p + 2] == 2, see vertex_gradient).
// False (b untouched) when those conditions fail.
bool fit_recenter(std::span<const int32_t> patch, const LogMapWorkspace& ws, double& bx, double& by) {
  const bool two_ring = !ws.coef2.empty();
  double N[3][3] = {}, r[3] = {}, ux = 0, uy = 0;
  int64_t cnt = 0;
  for (size_t p = 0; p < patch.size(); ++p) {
    if (ws.grad[3 * p + 2] != 2.0) continue;
    if (two_ring && std::binary_search(ws.sorted_sources.begin(), ws.sorted_sources.end(), patch[p])) continue;
    const double gx = ws.grad[3 * p], gy = ws.grad[3 * p + 1];
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
  if (!(cnt >= 16 && std::hypot(ux, uy) < 0.25 * static_cast<double>(cnt))) return false;
  // 3x3 solve by Cramer's rule (well conditioned when the directions go all round).
  auto det3 = [](const double M[3][3]) {
    return M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
           M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  };
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
  // A center shift beyond a third of the radius is no small vertex-level bias: keep the raw gradients.
  if (!(radius2 > 0 && sol[0] * sol[0] + sol[1] * sol[1] < radius2 / 9)) return false;
  bx = sol[0];
  by = sol[1];
  return true;
}

// Raw angles of the (recentered by (bx, by)) gradient directions, a SIMD batch
// of vertices at a time (xsimd::atan2, see docs/logmap.md): ws.theta holds the
// angle per patch vertex, then the recentered gradients' x and y (each padded
// to whole batches; returned: the padded length).
size_t raw_angles(size_t np, double bx, double by, LogMapWorkspace& ws) {
  using batch = xsimd::batch<double>;
  constexpr size_t Bw = batch::size;
  const size_t npad = (np + Bw - 1) / Bw * Bw;
  ws.theta.resize(3 * npad);
  double* gxs = ws.theta.data() + npad;
  double* gys = gxs + npad;
  for (size_t p = 0; p < np; ++p) {
    const bool usable = ws.grad[3 * p + 2] != 0;
    gxs[p] = ws.grad[3 * p] - (usable ? bx : 0.0);
    gys[p] = ws.grad[3 * p + 1] - (usable ? by : 0.0);
  }
  std::fill(gxs + np, gxs + npad, 0.0);
  std::fill(gys + np, gys + npad, 0.0);
  for (size_t p = 0; p < npad; p += Bw) {
    const batch gx = batch::load_unaligned(gxs + p), gy = batch::load_unaligned(gys + p);
    const auto zero = gx == batch(0.0) && gy == batch(0.0);
    xsimd::select(zero, batch(0.0), xsimd::atan2(gy, gx)).store_unaligned(ws.theta.data() + p);
  }
  return npad;
}
}  // namespace

// Pass 2, after every vertex_gradient of the patch and the distances: the
// corrections and the polar-to-Cartesian output.
void HeatLogMap::finish_angles(std::span<const int32_t> patch, const LogMapOutput& out, const LogMapEstimator& est,
                               LogMapStats& st, LogMapWorkspace& ws) const {
  const bool use_log = est.angle != LogMapAngle::HeatAverage;
  double bx = 0, by = 0;
  if (est.recenter && use_log && fit_recenter(patch, ws, bx, by)) st.recentered = true;
  const size_t npad = raw_angles(patch.size(), bx, by, ws);
  const double* gxs = ws.theta.data() + npad;  // the recentered gradient per patch vertex
  const double* gys = gxs + npad;
  const double* lattice = use_log && !ws.lattice.empty() ? ws.lattice.data() : nullptr;
  // Path correction: first-pass angles (raw + the center's table), then the
  // offsets of the lattice along each ray replace the table's.
  const bool path = lattice && est.lattice == LatticeCorrection::Path;
  if (path) {
    ws.path_angle.resize(patch.size());
    for (size_t p = 0; p < patch.size(); ++p)
      ws.path_angle[p] = std::remainder(ws.theta[p] + lattice_offset(lattice, ws.theta[p]), 2 * std::numbers::pi);
    path_offsets(patch, ws);
  }
  for (size_t p = 0; p < patch.size(); ++p) {
    const bool usable = ws.grad[3 * p + 2] != 0;
    const double gx = gxs[p], gy = gys[p];
    double th = ws.theta[p];
    if (!(lattice && usable) && (gx != 0 || gy != 0)) {
      // Polar to Cartesian from the direction itself (no cos / sin calls).
      // (hypot where the squares would underflow: the plain average of far, tiny heat values)
      const double g2 = gx * gx + gy * gy;
      const double il = g2 > 1e-280 ? 1 / std::sqrt(g2) : 1 / std::hypot(gx, gy);
      out.angle[p] = th;
      out.u[p] = gx * il;  // unit direction; scale_by_distance makes it (u, v)
      out.v[p] = gy * il;
      continue;
    }
    if (path && usable && (gx != 0 || gy != 0)) {
      th += path_offset_at(ws.path, th, ws.path_r[p], ws.path_rmax);
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

namespace {
// Thread CPU time per phase of a query (LogMapStats): lap(phase) stores the
// time since the previous lap.
struct PhaseClock {
  double tick = thread_cpu_seconds();
  void lap(double& phase) {
    const double now = thread_cpu_seconds();
    phase = now - tick;
    tick = now;
  }
};
}  // namespace

// All sources in one pass over the plan's supernodes (kernels/include/locus/kernels/solve/solve_wide.hpp),
// W lanes (|S| rounded up to a multiple of 8): the results stay in ws.wide's rows.
void HeatLogMap::solve_heat_one_pass(int32_t W, LogMapWorkspace& ws) const {
  const int32_t d = static_cast<int32_t>(ws.sources.size());
  ws.rhs_wide.assign(static_cast<size_t>(d) * W, 0.0);
  for (int32_t l = 0; l < d; ++l) ws.rhs_wide[static_cast<size_t>(l) * W + l] = 1.0;
  solve_planned_wide(geo_.heat_factor(), ws.plan, W, ws.rhs_wide, {}, ws.wide);
}

// After solve_heat_one_pass: the solver's rows are read once, in memory order,
// instead of gathered into region order first (see docs/logmap.md, "Kernel
// tuning"): each row gives the center's heat (lane 0, into ws.geo.h) for the
// distance and, at patch vertices, the gradient estimate.
void HeatLogMap::gradients_from_rows(int32_t W, int32_t center_local, const LogMapEstimator& est, LogMapStats& st,
                                     LogMapWorkspace& ws) const {
  const PatchRegion& r = ws.geo.region;
  const size_t nloc = r.verts.size();
  const int32_t np = r.patch_size;
  const HostVector<int32_t>& rows = ws.wide.out_rows;
  const double* X = ws.wide.x.data();
  const size_t xrows = ws.wide.x.size() / static_cast<size_t>(W);
  // Owner of each row: its region index, with kSourceBit set for the
  // sources (no lookups by vertex id inside the loop: those were cache misses).
  constexpr int32_t kSourceBit = 1 << 30;
  ws.row_owner.assign(xrows, -1);
  for (size_t k = 0; k < nloc; ++k) ws.row_owner[rows[k]] = static_cast<int32_t>(k);
  for (int32_t v : ws.sources)  // (the two-ring may reach beyond a tiny patch's region)
    if (r.local[v] >= 0) ws.row_owner[rows[r.local[v]]] |= kSourceBit;
  const double h_center = X[static_cast<size_t>(rows[center_local]) * W];
  for (size_t row = 0; row < xrows; ++row) {
    const int32_t o = ws.row_owner[row];
    if (o < 0) continue;
    const int32_t k = o & (kSourceBit - 1);
    const double* f = X + row * static_cast<size_t>(W);
    ws.geo.h[k] = f[0];
    if (k < np)
      vertex_gradient(static_cast<size_t>(k), k == center_local, (o & kSourceBit) != 0, f, true, h_center, est, st, ws);
  }
}

// More than kMaxWideLanes sources (valence > 31): `passes` wide solves of W
// lanes, gathered into ws.heat (region order, W * passes values per vertex).
void HeatLogMap::solve_heat_passes(int32_t W, int32_t passes, LogMapWorkspace& ws) const {
  const int32_t d = static_cast<int32_t>(ws.sources.size());
  const size_t nloc = ws.geo.region.verts.size();
  ws.heat.resize(nloc * static_cast<size_t>(W) * passes);
  const int64_t stride = static_cast<int64_t>(W) * passes;
  for (int32_t ps = 0; ps < passes; ++ps) {
    const int32_t k0 = ps * W, lanes = std::min(W, d - k0);
    ws.rhs_wide.assign(static_cast<size_t>(d) * W, 0.0);
    for (int32_t l = 0; l < lanes; ++l) ws.rhs_wide[static_cast<size_t>(k0 + l) * W + l] = 1.0;
    ws.out_wide.resize(nloc * static_cast<size_t>(W));
    solve_planned_wide(geo_.heat_factor(), ws.plan, W, ws.rhs_wide, ws.out_wide, ws.wide);
    for (size_t v = 0; v < nloc; ++v)
      std::copy_n(ws.out_wide.begin() + static_cast<int64_t>(v) * W, W, ws.heat.begin() + static_cast<int64_t>(v) * stride + k0);
  }
}

// After solve_heat_passes: the center's heat per region vertex and the
// gradient estimate per patch vertex (patch index = region index).
void HeatLogMap::gradients_from_passes(std::span<const int32_t> patch, int32_t center, int32_t center_local,
                                       size_t stride, const LogMapEstimator& est, LogMapStats& st,
                                       LogMapWorkspace& ws) const {
  const size_t nloc = ws.geo.region.verts.size();
  for (size_t v = 0; v < nloc; ++v) ws.geo.h[v] = ws.heat[v * stride];
  const double h_center = ws.heat[static_cast<size_t>(center_local) * stride];
  for (size_t p = 0; p < patch.size(); ++p)
    vertex_gradient(p, patch[p] == center,
                    std::binary_search(ws.sorted_sources.begin(), ws.sorted_sources.end(), patch[p]),
                    ws.heat.data() + p * stride, false, h_center, est, st, ws);
}

namespace {
void check_center_vertex(int32_t center, int32_t n) {
  if (center < 0 || center >= n)
    fail(ErrorCode::BadUsage, "center " + std::to_string(center) + " is not a vertex (the mesh has " +
                                  std::to_string(n) + " vertices)");
}
}  // namespace

LogMapStats HeatLogMap::query(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                              LogMapWorkspace& ws, const LogMapEstimator& estimator) const {
  const int32_t n = num_vertices();
  check_center_vertex(center, n);
  check_outputs(out, patch.size());
  PhaseClock clock;
  PatchRegion& r = ws.geo.region;
  geo_.build_region(patch, r);
  LogMapStats st;
  clock.lap(st.region_s);
  try {
    const int32_t cl = r.local[center];
    if (cl < 0 || cl >= r.patch_size)
      fail(ErrorCode::BadUsage, "the center vertex " + std::to_string(center) + " is not in the patch");
    check_same_component(geo_, center, patch);
    const LogMapEstimator est = prepare_center(center, estimator, ws);
    clock.lap(st.center_s);
    st.two_ring = !ws.coef2.empty();
    const int32_t d = static_cast<int32_t>(ws.sources.size());
    const size_t nloc = r.verts.size();
    st.sources = d;
    st.batches = (d + kLanes - 1) / kLanes;
    st.region_size = static_cast<int32_t>(nloc);
    plan_subset_solve(*geo_.heat_factor().symbolic, geo_.vertex_supernodes(), ws.sources, r.verts, ws.plan,
                      ws.plan_ws);
    clock.lap(st.plan_s);
    // Lanes rounded up to a multiple of 8; more than kMaxWideLanes sources
    // (valence > 31) take further passes into the same rows.
    const int32_t W = std::min(kMaxWideLanes, (d + kLanes - 1) / kLanes * kLanes);
    st.passes = (d + W - 1) / W;
    ws.geo.h.resize(nloc);
    begin_gradients(patch.size(), ws);
    if (st.passes == 1) {
      solve_heat_one_pass(W, ws);
      clock.lap(st.heat_s);
      gradients_from_rows(W, cl, est, st, ws);
    } else {
      solve_heat_passes(W, st.passes, ws);
      clock.lap(st.heat_s);
      gradients_from_passes(patch, center, cl, static_cast<size_t>(W) * st.passes, est, st, ws);
    }
    double t_gradients = 0;
    clock.lap(t_gradients);
    // Distance from lane 0 (the heat from the center).
    geo_.distance_from_heat(r, ws.geo.h, cl, out.distance, ws.geo, opt_.geodesic.poisson_rhs, &ws.plan);
    clock.lap(st.distance_s);
    st.poisson_s = ws.geo.poisson_s;
    st.underflow = ws.geo.underflow;
    st.t_no_underflow = ws.geo.t_no_underflow;
    finish_angles(patch, out, est, st, ws);
    scale_by_distance(out);
    st.angles_s = t_gradients;
  } catch (...) {
    geo_.release_region(r);
    throw;
  }
  geo_.release_region(r);
  double t_finish = 0;
  clock.lap(t_finish);  // (finish_angles and the output, with the region's release)
  st.angles_s += t_finish;
  return st;
}

LogMapStats HeatLogMap::query_full(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                                   LogMapWorkspace& ws, const LogMapEstimator& estimator) const {
  const int32_t n = num_vertices();
  check_center_vertex(center, n);
  check_outputs(out, patch.size());
  bool has_center = false;
  for (int32_t v : patch) {
    if (v < 0 || v >= n) fail(ErrorCode::BadUsage, "patch vertex " + std::to_string(v) + " is out of range");
    has_center |= v == center;
  }
  if (!has_center) fail(ErrorCode::BadUsage, "the center vertex " + std::to_string(center) + " is not in the patch");
  check_same_component(geo_, center, patch);
  const LogMapEstimator est = prepare_center(center, estimator, ws);
  const int32_t d = static_cast<int32_t>(ws.sources.size());
  LogMapStats st;
  st.two_ring = !ws.coef2.empty();
  st.sources = d;
  st.batches = (d + kLanes - 1) / kLanes;
  st.region_size = n;
  const NumericFactor& F = geo_.heat_factor();
  ws.heat.resize(static_cast<size_t>(n) * d);
  ws.out8.resize(static_cast<size_t>(n) * kLanes);
  ws.work_full.resize(solve_work_size(F, kLanes));
  for (int32_t bt = 0; bt < st.batches; ++bt) {
    std::fill(ws.out8.begin(), ws.out8.end(), 0.0);
    const int32_t k0 = bt * kLanes, lanes = std::min(kLanes, d - k0);
    for (int32_t l = 0; l < lanes; ++l) ws.out8[static_cast<size_t>(ws.sources[k0 + l]) * kLanes + l] = 1.0;
    solve8(F, ws.out8, ws.work_full);
    for (int32_t v = 0; v < n; ++v)
      for (int32_t l = 0; l < lanes; ++l)
        ws.heat[static_cast<size_t>(v) * d + k0 + l] = ws.out8[static_cast<size_t>(v) * kLanes + l];
  }
  HostVector<double>& h0 = ws.geo.h;
  h0.resize(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) h0[v] = ws.heat[static_cast<size_t>(v) * d];
  ws.dist_full.resize(static_cast<size_t>(n));
  geo_.distance_from_heat_full(h0, center, ws.dist_full, ws.geo);
  for (size_t p = 0; p < patch.size(); ++p) out.distance[p] = ws.dist_full[patch[p]];
  st.underflow = 0;  // (the whole-mesh count above is not the patch's)
  for (int32_t v : patch)
    if (!(h0[v] >= std::numeric_limits<double>::min())) ++st.underflow;
  st.t_no_underflow = st.underflow > 0 ? ws.geo.t_no_underflow : 0.0;
  // Rows of ws.heat are vertex ids.
  begin_gradients(patch.size(), ws);
  const double h_center = ws.heat[static_cast<size_t>(center) * d];
  for (size_t p = 0; p < patch.size(); ++p)
    vertex_gradient(p, patch[p] == center,
                    std::binary_search(ws.sorted_sources.begin(), ws.sorted_sources.end(), patch[p]),
                    ws.heat.data() + static_cast<size_t>(patch[p]) * d, false, h_center, est, st, ws);
  finish_angles(patch, out, est, st, ws);
  scale_by_distance(out);
  return st;
}

int64_t count_flipped_triangles(const TriangleGradients& g, std::span<const int32_t> patch,
                                std::span<const double> u, std::span<const double> v, std::vector<int32_t>& local) {
  if (local.size() != static_cast<size_t>(g.nv)) local.assign(g.nv, -1);
  if (u.size() != patch.size() || v.size() != patch.size())
    fail(ErrorCode::BadUsage, "count_flipped_triangles: u and v need one entry per patch vertex");
  for (int32_t i : patch)
    if (i < 0 || i >= g.nv) fail(ErrorCode::BadUsage, "count_flipped_triangles: vertex " + std::to_string(i) + " out of range");
  for (size_t p = 0; p < patch.size(); ++p) local[patch[p]] = static_cast<int32_t>(p);
  int64_t flipped = 0;
  for (size_t p = 0; p < patch.size(); ++p) {
    const int32_t i = patch[p];
    for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
      const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(g.vf_faces[q]);
      // Count each face once: at its lowest-numbered corner.
      if (i != std::min({t[0], t[1], t[2]})) continue;
      const int32_t a = local[t[0]], b = local[t[1]], c = local[t[2]];
      if (a < 0 || b < 0 || c < 0) continue;
      const double area = (u[b] - u[a]) * (v[c] - v[a]) - (u[c] - u[a]) * (v[b] - v[a]);
      if (area < 0) ++flipped;
    }
  }
  for (int32_t i : patch) local[i] = -1;
  return flipped;
}

double injectivity_radius(const TriangleGradients& g, std::span<const int32_t> patch, std::span<const double> u,
                          std::span<const double> v, std::span<const double> distance, std::vector<int32_t>& local) {
  if (local.size() != static_cast<size_t>(g.nv)) local.assign(g.nv, -1);
  if (u.size() != patch.size() || v.size() != patch.size() || distance.size() != patch.size())
    fail(ErrorCode::BadUsage, "injectivity_radius: u, v and distance need one entry per patch vertex");
  for (int32_t i : patch)
    if (i < 0 || i >= g.nv) fail(ErrorCode::BadUsage, "injectivity_radius: vertex " + std::to_string(i) + " out of range");
  for (size_t p = 0; p < patch.size(); ++p) local[patch[p]] = static_cast<int32_t>(p);
  double radius = std::numeric_limits<double>::infinity();
  for (size_t p = 0; p < patch.size(); ++p) {
    const int32_t i = patch[p];
    for (int64_t q = g.vf_offsets[i]; q < g.vf_offsets[i + 1]; ++q) {
      const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(g.vf_faces[q]);
      if (i != std::min({t[0], t[1], t[2]})) continue;  // each face once
      const int32_t a = local[t[0]], b = local[t[1]], c = local[t[2]];
      if (a < 0 || b < 0 || c < 0) continue;
      const double area = (u[b] - u[a]) * (v[c] - v[a]) - (u[c] - u[a]) * (v[b] - v[a]);
      // A flipped face lies inside every disk that holds its farthest corner.
      if (area < 0) radius = std::min(radius, std::max({distance[a], distance[b], distance[c]}));
    }
  }
  for (int32_t i : patch) local[i] = -1;
  return radius;
}

}  // namespace locus
