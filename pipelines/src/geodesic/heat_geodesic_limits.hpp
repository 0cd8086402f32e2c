// What the heat method can answer and what it refuses (heat_geodesic_limits.cpp),
// shared by the files of HeatGeodesic (heat_geodesic.cpp, heat_geodesic_region.cpp).
// Internal: not installed.
#pragma once
#include <cstdint>
#include <span>

#include "locus/kernels/mesh/mesh_gradient.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus::heat_geodesic_limits {

// How many patch vertices (or faces) ahead the region walks prefetch.
inline constexpr int32_t kAhead = 8;

// The longest diffusion time, as a multiple of h^2. The heat's variation
// between neighbours relative to its value falls like h D / t (D the mesh's
// size): far beyond D^2 the heat is uniform up to rounding and its gradient
// has no direction (at 1e300 h^2, 2,673 of the 2,775 distances of a mesh came
// out negative). A limit in units of h^2 is the same for every mesh and far
// above any useful time: the distance is smooth from about D^2 on.
inline constexpr double kMaxTFactor = 1e6;

// Error(BadInput) naming a needle triangle (an angle within 1e-6 rad of 0 or pi).
void check_needles(const Mesh& m);
// Error(BadUsage) naming the limit when t_factor > kMaxTFactor.
void check_time(double t_factor);
// A scaled by a power of two when its mean diagonal entry is far from 1 (the
// heat's magnitude on meshes of extreme size); unchanged otherwise.
void normalize_heat_operator(CscMatrix& A);
// Error(ResourceLimit) when `held_bytes` (per-mesh data and both operators)
// plus two factorizations of S exceed memory_limit_bytes(ctx).
void check_memory(int32_t nv, double held_bytes, const SymbolicFactor& S, const RunContext& ctx);
// Error(Numerical) naming the vertex (ids[k], or k when ids is empty) of a
// distance below zero beyond rounding, or not a number. With dip_tolerance > 0
// (an absolute distance), dips no deeper than it on at most 1% of the vertices
// (at least one) are set to 0 instead and counted in `dips` / `deepest_dip`.
void check_distances(std::span<double> distance, std::span<const int32_t> ids, double t_factor,
                     double dip_tolerance, int64_t& dips, double& deepest_dip);

}  // namespace locus::heat_geodesic_limits
