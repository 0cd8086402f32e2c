// The Path lattice correction of the heat log map (LatticeCorrection::Path,
// the default at regular stars; pipelines/include/locus/pipelines/geodesic/logmap.hpp;
// thesis §6.6; the dispersion relation: logmap_lattice.cpp). Measurements:
// docs/logmap.md.
//
// First-order picture: far from j, log h_j ~ -D(x, j) with D the lattice's
// Finsler distance, whose unit ball varies with position; along the ray from
// i to j, grad_x D(i, j) is (to first order) the dual direction of the Finsler
// norm averaged over the ray, plus a transverse term from the norm's
// variation. This takes the first part: per sector of the first-pass map
// (kPathSectors, with its two neighbors) and per radius R (kPathBins up to the
// patch's largest distance), the dispersion relations of the stars of the
// patch vertices in the sector with r < R, summed with weight mass / r
// (uniform per unit length), plus the center's star; each star's edges turned
// into i's tangent plane by the minimal rotation of its normal onto n_i,
// projected and rescaled to their length. The offset at a vertex interpolates
// linearly in sector and radius, from the center's own offset at r = 0.
//
// Phi(k) = sum w (exp(k.e) - 1) and its gradient, summed over many stars, go
// through the moments M[d][a] = sum w x^a y^(d-a) of the edges (x, y) = e / h,
// degrees 1..kPathDegree (Taylor series of exp; |k.e| <~ 1.5 at t = h^2, so the
// remainder is below 1.5^11 / 11! ~ 2e-6 of the sum; same E_a as the direct
// sums to 4 digits, docs/logmap.md): one pass over each star, and every
// (sector, radius) sum is a sum of a few cells' moments.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "locus/pipelines/geodesic/logmap.hpp"
#include "logmap_parts.hpp"

namespace locus {

namespace {
constexpr int kPathSectors = 64, kPathBins = 6, kPathDegree = 10;
// Edge moments per (sector, radius) cell: monomials of degree 0..kPathDegree,
// x^a y^(d - a) at path_monomial(d, a), then the cell's weighted mass.
constexpr int kPathMonomials = (kPathDegree + 1) * (kPathDegree + 2) / 2;
constexpr int path_monomial(int d, int a) { return d * (d + 1) / 2 + a; }
// Newton's relative tolerance for the sectors' radii (a truncated series: no
// point in the last digits).
constexpr double kPathNewtonTol = 1e-12;

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
// Compile-time constants, so that the compiler folds them into the sums below
// (a division by 0! = 1! = 1 disappears); the results depend on that folding
// to the last bit.
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
constexpr PathTaylorTables kPathTaylor;

// The Path table of one sector: for radius bins 0..kPathBins, the cumulative
// sum of its and its two neighbors' cells of `mom` (from the center's cell at
// bin 0), the dispersion set's radius in the sector's direction (Newton on the
// Taylor series through the moments) and the offset of the direction to j,
// into out[0..kPathBins] (0 where Newton fails or the offset is not small).
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
    const bool ok = newton_dispersion_radius(rho, kPathNewtonTol, [&](double r) {
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
      if (!(std::abs(off) < kMaxLatticeOffset)) off = 0;
    }
    out[b] = off;
  }
}
}  // namespace

double path_offset_at(const HostVector<double>& table, double th, double r, double rmax) {
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

// One star's dispersion relation for the Path table: v's star turned into i's
// tangent plane (normal n, frame e1, e2), in units of h (inv_h = 1 / h); its
// moments, times `weight`, go to `cell`, weight * v's lumped mass to its last entry.
void HeatLogMap::add_path_star(int32_t v, double weight, const double n[3], const double e1[3], const double e2[3],
                               double inv_h, double* cell, DispersionStarScratch& star) const {
  star.edges.clear();
  add_star_edges(v, StarFrame{n, e1, e2, inv_h}, weight, cell[kPathMonomials], star);
  add_edge_moments(star.edges, cell);
}

// The table from the first-pass angles (pw.angle) and heat radii (pw.r) of
// the patch vertices around center i.
void HeatLogMap::path_offsets(std::span<const int32_t> patch, int32_t i, LogMapPathWorkspace& pw) const {
  double n[3], e1[3], e2[3];
  frame(i, n, e1, e2);
  const HostVector<double>& radius = pw.r;
  double rmax = 0;
  for (size_t p = 0; p < patch.size(); ++p)
    if (std::isfinite(radius[p])) rmax = std::max(rmax, radius[p]);
  pw.rmax = rmax > 0 ? rmax : 1.0;
  const double h = geo_.mean_edge_length(), inv_h = 1 / h, dtheta = 2 * std::numbers::pi / kPathSectors;
  constexpr int NM = kPathMonomials;
  const size_t cells = static_cast<size_t>(kPathSectors) * kPathBins;
  HostVector<double>& mom = pw.moments;
  mom.assign((cells + 1) * (NM + 1), 0.0);  // per cell: NM moments, then the weighted mass; last: the center
  // The center's star (weight: the length h it stands for), then each patch
  // vertex in its cell, weight ~ 1 / (r * 3 sectors' angle): uniform per unit
  // length along the ray.
  add_path_star(i, h, n, e1, e2, inv_h, mom.data() + cells * (NM + 1), pw.star);
  for (size_t p = 0; p < patch.size(); ++p) {
    if (patch[p] == i || !std::isfinite(radius[p])) continue;
    const double r = radius[p], th = pw.angle[p];
    const int sct = static_cast<int>(std::floor((th < 0 ? th + 2 * std::numbers::pi : th) / dtheta)) % kPathSectors;
    const int b = std::min(kPathBins - 1, static_cast<int>(r / pw.rmax * kPathBins));
    add_path_star(patch[p], 1.0 / (std::max(r, h) * 3 * dtheta), n, e1, e2, inv_h,
                  mom.data() + (static_cast<size_t>(sct) * kPathBins + b) * (NM + 1), pw.star);
  }
  // Per sector: the cumulative sum over radius bins of its and its neighbors' cells.
  pw.table.assign(static_cast<size_t>(kPathSectors) * (kPathBins + 1), 0.0);
  for (int sct = 0; sct < kPathSectors; ++sct)
    path_sector_offsets(sct, mom.data(), h, geo_.time(), pw.table.data() + static_cast<size_t>(sct) * (kPathBins + 1));
}

}  // namespace locus
