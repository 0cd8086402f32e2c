// Internal to the heat log map (pipelines/include/locus/pipelines/geodesic/logmap.hpp,
// thesis §6.5-6.6): what its files hand each other. One section per file:
// logmap_frame.cpp (frames, star classes), logmap_lattice.cpp (dispersion
// stars, the star/ring table, the Newton step the Path table shares),
// logmap_path.cpp (the Path table), logmap_recenter.cpp (the recenter fit).
#pragma once
#include <cmath>
#include <cstdint>
#include <span>

#include "locus/pipelines/geodesic/logmap.hpp"

namespace locus {

inline double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The corner of face f at its vertex v: the face's other two corners in the
// face's order (a follows v, b follows a).
inline void star_corner(const TriangleGradients& g, int32_t f, int32_t v, int32_t& a, int32_t& b) {
  const int32_t* t = g.tri.data() + 3 * static_cast<int64_t>(f);
  const int s = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
  a = t[(s + 1) % 3];
  b = t[(s + 2) % 3];
}

// ---- logmap_lattice.cpp

// How HeatLogMap::add_star_edges writes a star's edges in the center's
// tangent frame (e1, e2): with `normal` (the center's), each edge is first
// turned by the minimal rotation taking the star vertex's normal onto it (the
// Path table, whose stars lie away from the center); without, projected as it
// is (the star and ring tables). Projected edges are rescaled to their length
// times `unit` (1 / h for the Path moments).
struct HeatLogMap::StarFrame {
  const double* normal;
  const double* e1;
  const double* e2;
  double unit;
};

// Table angles of the star/ring lattice correction over [0, 2 pi).
constexpr int kLatticeTable = 128;
// A correction is a small turn of the gradient direction: an offset of half a
// radian or more means the plane-wave picture does not hold at this center,
// and no correction is applied.
constexpr double kMaxLatticeOffset = 0.5;

// The star/ring table's offset at angle th: periodic over [0, 2 pi), linear interpolation.
double lattice_offset(const double* table, double th);

// Newton for the dispersion set's radius rho > 0 in one direction, shared by the
// star/ring table (exponential sums) and the Path table (Taylor moments):
// eval(rho) gives (f, f') with f' > 0 on a convex set. False when it leaves that
// regime (the caller then applies no correction); rho holds the last iterate.
template <class Eval>
bool newton_dispersion_radius(double& rho, double tol, Eval eval) {
  constexpr int kMaxIterations = 60;  // quadratic convergence needs a handful; 60 only bounds a failure
  for (int it = 0; it < kMaxIterations; ++it) {
    const auto [f, df] = eval(rho);
    if (!(df > 0) || !std::isfinite(f)) return false;
    const double step = f / df;
    rho -= step;
    if (!(rho > 0)) return false;
    if (std::abs(step) <= tol * rho) return true;
  }
  return false;
}

// ---- logmap_path.cpp

// The Path table's offset at angle th and heat radius r (rmax: the largest),
// interpolated linearly in sector and radius from the center's own offset at r = 0.
double path_offset_at(const HostVector<double>& table, double th, double r, double rmax);

// ---- logmap_recenter.cpp

// The direction-independent part (bx, by) of the patch's far-field gradients
// (see logmap_recenter.cpp); false (b untouched) when the patch does not
// surround the center or the fit is not a small shift.
bool fit_recenter(std::span<const int32_t> patch, const LogMapEstimatorWorkspace& ws, double& bx, double& by);

}  // namespace locus
