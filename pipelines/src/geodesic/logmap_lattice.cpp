// Lattice (dispersion) correction of the heat log map's direction from the
// center's star or ring (LatticeCorrection::Star, Ring; pipelines/include/locus/pipelines/geodesic/logmap.hpp;
// thesis §6.6), and the dispersion stars the Path table (logmap_path.cpp)
// shares. Measurements: docs/logmap.md, "Angle estimators".
//
// Far from its source j the discrete heat h_j = A^{-1} e_j behaves locally
// like a plane wave exp(k . x), and at vertex v (A exp(k . x))_v = 0 gives the
// dispersion relation
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
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "locus/pipelines/geodesic/logmap.hpp"
#include "logmap_parts.hpp"

namespace locus {

namespace {
// Newton's relative tolerance for the table's radii (exponential sums, exact to rounding).
constexpr double kLatticeNewtonTol = 1e-13;
// Below this cosine between a star's normal and the center's (about 154
// degrees) the minimal rotation's 1 / (1 + cos) blows up: no rotation then.
constexpr double kMinRotationCos = -0.9;
}  // namespace

double lattice_offset(const double* table, double th) {
  const double pos = (th < 0 ? th + 2 * std::numbers::pi : th) * (kLatticeTable / (2 * std::numbers::pi));
  const int a0 = std::min(kLatticeTable - 1, static_cast<int>(pos));
  const double w = pos - a0;
  return (1 - w) * table[a0] + w * table[(a0 + 1) % kLatticeTable];
}

// Appends v's star to star.edges: one (x, y, weight * cotan weight) per edge
// (v, u), an interior edge met from two faces once with its two half
// cotangents summed, written in the center's frame as `frame` says; adds
// weight * v's lumped mass (a third of each face) to `mass`.
void HeatLogMap::add_star_edges(int32_t v, const StarFrame& frame, double weight, double& mass,
                                DispersionStarScratch& star) const {
  const TriangleGradients& g = geo_.gradients();
  // R x = x + c x x + c x (c x x) / (1 + cos), c = n_v x n: the minimal
  // rotation taking n_v to the center's n (none for antiparallel normals).
  double c[3] = {0, 0, 0}, k = 0;
  if (frame.normal) {
    const double* nv = normal_.data() + 3 * static_cast<size_t>(v);
    const double* n = frame.normal;
    c[0] = nv[1] * n[2] - nv[2] * n[1], c[1] = nv[2] * n[0] - nv[0] * n[2], c[2] = nv[0] * n[1] - nv[1] * n[0];
    const double cosa = dot3(nv, n);
    k = cosa > kMinRotationCos ? 1 / (1 + cosa) : 0.0;
  }
  const size_t first = star.edges.size() / 3;  // v's entries start here
  star.ends.clear();
  for (int64_t q = g.vf_offsets[v]; q < g.vf_offsets[v + 1]; ++q) {
    const int32_t f = g.vf_faces[q];
    int32_t a, b;
    star_corner(g, f, v, a, b);
    mass += weight * g.area[f] / 3;
    const double pa[3] = {x_[a] - x_[v], y_[a] - y_[v], z_[a] - z_[v]};
    const double pb[3] = {x_[b] - x_[v], y_[b] - y_[v], z_[b] - z_[v]};
    const double twice = 2 * g.area[f];
    // Edge (v, a) gets half the cotangent at b, edge (v, b) half the one at a:
    // cot b = (v - b) . (a - b) / 2A, cot a = (v - a) . (b - a) / 2A.
    const double w[2] = {0.5 * (dot3(pb, pb) - dot3(pa, pb)) / twice, 0.5 * (dot3(pa, pa) - dot3(pa, pb)) / twice};
    const double* edges[2] = {pa, pb};
    const int32_t ends_of[2] = {a, b};
    for (int e = 0; e < 2; ++e) {
      const size_t seen = static_cast<size_t>(std::find(star.ends.begin(), star.ends.end(), ends_of[e]) - star.ends.begin());
      if (seen < star.ends.size()) {
        star.edges[3 * (first + seen) + 2] += weight * w[e];
        continue;
      }
      const double* x = edges[e];
      double rx[3] = {x[0], x[1], x[2]};
      if (frame.normal) {
        const double cx[3] = {c[1] * x[2] - c[2] * x[1], c[2] * x[0] - c[0] * x[2], c[0] * x[1] - c[1] * x[0]};
        const double ccx[3] = {c[1] * cx[2] - c[2] * cx[1], c[2] * cx[0] - c[0] * cx[2], c[0] * cx[1] - c[1] * cx[0]};
        for (int j = 0; j < 3; ++j) rx[j] = x[j] + cx[j] + k * ccx[j];
      }
      double ex = dot3(rx, frame.e1), ey = dot3(rx, frame.e2);
      const double l2 = ex * ex + ey * ey;
      if (l2 > 0) {  // projected, rescaled to the edge's length (normal coordinates)
        const double sc = std::sqrt(dot3(x, x) / l2) * frame.unit;
        ex *= sc;
        ey *= sc;
      }
      star.ends.push_back(ends_of[e]);
      star.edges.push_back(ex);
      star.edges.push_back(ey);
      star.edges.push_back(weight * w[e]);
    }
  }
}

void HeatLogMap::prepare_lattice(const double e1[3], const double e2[3], std::span<const int32_t> stars,
                                 LogMapLatticeWorkspace& lw) const {
  HostVector<double>& st = lw.star.edges;
  st.clear();
  double mass = 0;
  for (int32_t v : stars) add_star_edges(v, StarFrame{nullptr, e1, e2, 1.0}, 1.0, mass, lw.star);
  const double target = mass / geo_.time();
  const size_t ne = st.size() / 3;
  lw.table.resize(kLatticeTable);
  double rho = 1.0 / std::sqrt(geo_.time());
  for (int a = 0; a < kLatticeTable; ++a) {
    const double psi = 2 * std::numbers::pi * a / kLatticeTable;
    const double ux = std::cos(psi), uy = std::sin(psi);
    const bool ok = newton_dispersion_radius(rho, kLatticeNewtonTol, [&](double r) {
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
      lw.table.clear();
      return;
    }
    double gx = 0, gy = 0;
    for (size_t e = 0; e < ne; ++e) {
      const double c = ux * st[3 * e] + uy * st[3 * e + 1];
      const double x = st[3 * e + 2] * std::exp(-rho * c);
      gx -= x * st[3 * e];
      gy -= x * st[3 * e + 1];
    }
    lw.table[a] = std::remainder(std::atan2(gy, gx) - psi, 2 * std::numbers::pi);
    if (!(std::abs(lw.table[a]) < kMaxLatticeOffset)) {
      lw.table.clear();
      return;
    }
  }
}

}  // namespace locus
