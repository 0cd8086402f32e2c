// What the heat method can answer and what it refuses (heat_geodesic_limits.hpp;
// thesis §6.4.1, after Crane et al. 2013, who note the same limits): needle
// triangles, diffusion times so long that the heat has no direction, the
// heat's magnitude on meshes of extreme size, the memory of both factors
// together, and distances that are no answer. Each refusal names what is wrong
// and where; on meshes of ordinary size nothing here changes a result.
#include "heat_geodesic_limits.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "locus/core/format_significant.hpp"
#include "locus/error.hpp"
#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus::heat_geodesic_limits {

namespace {

std::string short_number(double v) { return format_significant(v, 6); }

}  // namespace

// Needle triangles: an angle within kMinAngle of 0 or pi gives cotangent
// weights beyond 1 / kMinAngle. The factorizations still succeed, but the
// distance silently loses all accuracy (measured on a 5x5 planar grid with one
// needle, max error against the Euclidean distance: 0.105 without the needle,
// 0.125 at |cot| ~ 3e5, 0.15 at 3e6, 0.23-0.41 at 1e7-3e7, 0.66 at 3e8: the
// result is then meaningless). Refused by name instead of answered wrongly.
constexpr double kMinAngle = 1e-6;  // radians

void check_needles(const Mesh& m) {
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    cancel_point(f);
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int k = 0; k < 3; ++k) {
      const int32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
      double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], uz = m.z[b] - m.z[a];
      double wx = m.x[c] - m.x[a], wy = m.y[c] - m.y[a], wz = m.z[c] - m.z[a];
      const double sc = power_of_two_scale(std::max({std::abs(ux), std::abs(uy), std::abs(uz), std::abs(wx),
                                                     std::abs(wy), std::abs(wz)}));
      ux *= sc, uy *= sc, uz *= sc, wx *= sc, wy *= sc, wz *= sc;  // exact; no underflow at tiny scales
      const double cx = uy * wz - uz * wy, cy = uz * wx - ux * wz, cz = ux * wy - uy * wx;
      const double angle = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), ux * wx + uy * wy + uz * wz);
      if (angle < kMinAngle || angle > M_PI - kMinAngle) {
        char deg[32];
        std::snprintf(deg, sizeof deg, "%.3g", angle * 180.0 / M_PI);
        fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has an angle of " +
                                      deg + " degrees at vertex " + std::to_string(a) +
                                      " (a needle): heat geodesic distances lose all accuracy there; remesh or remove it");
      }
    }
  }
}

void check_time(double t_factor) {
  if (t_factor > kMaxTFactor)
    fail(ErrorCode::BadUsage, "heat geodesic: the diffusion time " + short_number(t_factor) +
                                  " h^2 is too long: it must be at most " + short_number(kMaxTFactor) +
                                  " h^2 (h the mean edge length; the default is 4 h^2). Beyond that the heat is "
                                  "nearly uniform, its gradient is lost to rounding and distances come out negative");
}

// The heat's magnitude: A^{-1} e_s is about 1 / M_ss ~ 1 / h^2, so on a mesh
// of size 1e149 (coordinate_range.hpp) the source's own heat is ~1e-296 and it
// underflows a few edges away, and the underflow note then asked for the time
// it already had. Scaling A by 2^-k (exact) scales every heat value by 2^k and
// nothing the method reads changes: unit directions, differences of log h,
// level sets of -log h. Meshes whose mean diagonal entry lies within
// 2^(+-kFreeExponent) of 1 are left as they are, bit for bit.
constexpr int kFreeExponent = 128;

void normalize_heat_operator(CscMatrix& A) {
  double sum = 0;
  for (int32_t j = 0; j < A.ncols; ++j) sum += A.values[A.colptr[j]];
  const double mean = A.ncols > 0 ? sum / A.ncols : 1.0;
  if (!(mean > 0) || !std::isfinite(mean)) return;  // the factorization names the column
  const int e = std::ilogb(mean);
  if (e >= -kFreeExponent && e <= kFreeExponent) return;
  const double scale = std::ldexp(1.0, -(e & ~1));  // an even power: the factor scales by an exact power too
  for (double& v : A.values) v *= scale;
}

// What the method holds once factored: the per-mesh data of prepare(), both
// operators and both factors (they are made side by side, each with its own
// workspace). Each factorization checks its own size too, but only against the
// whole limit; together with the mesh's derived data they could exceed it.
void check_memory(int32_t nv, double held_bytes, const SymbolicFactor& S, const RunContext& ctx) {
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  const double factors = 2.0 * static_cast<double>(estimate_factor_memory(S, threads).total_bytes);
  const double total = held_bytes + factors, limit = static_cast<double>(memory_limit_bytes(ctx));
  if (total <= limit) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  fail(ErrorCode::ResourceLimit,
       "heat geodesic on " + std::to_string(nv) + " vertices needs about " + short_number(total / kGiB) +
           " GiB (two factors " + short_number(factors / kGiB) + " GiB, operators and per-triangle data " +
           short_number(held_bytes / kGiB) + " GiB), more than the memory limit of " +
           short_number(limit / kGiB) + " GiB; raise it with --max-memory (RunContext::max_memory_bytes), or use a coarser mesh");
}

// A distance is a number >= 0 in the source's component (+inf in the others).
// The Poisson step's shift puts 0 at the source, and the discrete solution may
// dip below it near the source by a rounding-sized amount; a value further below
// (kNegativeSlack of the largest distance) or not a number means the heat carried
// no usable direction: refused, naming the vertex, never returned as a distance;
// unless the caller allows shallow dips (the robust operator's last resort):
// a few vertices a small fraction of an edge below zero are a discretization
// error of the Poisson step, set to 0 and reported.
constexpr double kNegativeSlack = 1e-9;

void check_distances(std::span<double> distance, std::span<const int32_t> ids, double t_factor,
                     double dip_tolerance, int64_t& dips, double& deepest_dip) {
  dips = 0;
  deepest_dip = 0;
  double dmax = 0;
  for (double d : distance)
    if (d < std::numeric_limits<double>::infinity()) dmax = std::max(dmax, d);
  int64_t below = 0, first = -1;
  bool shallow = true;
  for (size_t k = 0; k < distance.size(); ++k) {
    const double d = distance[k];
    if (d >= -kNegativeSlack * dmax) continue;
    ++below;
    if (first < 0) first = static_cast<int64_t>(k);
    shallow = shallow && d >= -dip_tolerance;  // false for NaN too
  }
  if (below == 0) return;
  const int64_t allowed = std::max<int64_t>(1, static_cast<int64_t>(distance.size()) / 100);
  if (dip_tolerance > 0 && shallow && below <= allowed) {
    for (double& d : distance)
      if (d < -kNegativeSlack * dmax) deepest_dip = std::max(deepest_dip, -d), d = 0.0;
    dips = below;
    return;
  }
  const double d = distance[first];
  const int32_t v = ids.empty() ? static_cast<int32_t>(first) : ids[first];
  fail(ErrorCode::Numerical, "heat geodesic: the distance at vertex " + std::to_string(v) + " is " +
                                 (std::isnan(d) ? std::string("not a number") : "negative (" + short_number(d) + ")") +
                                 " at t = " + short_number(t_factor) +
                                 " h^2: the heat carries no direction there; a shorter time (the default 4 h^2) avoids it",
       ErrorLocation{v, -1});
}

}  // namespace locus::heat_geodesic_limits
