// Harmonic parameterization of a surface patch from the GLOBAL factor
// (thesis §4.4, eq. 4.6, Figs. 4.5-4.7).
//
// The global factor of the regularized Laplacian K = -L_C + eps M of the whole
// mesh knows nothing of the patch boundary, so Dirichlet data is not an option;
// the thesis prescribes Neumann data instead: lay the patch's boundary loop
// B_0, B_1, ... out in the plane and set, per boundary vertex B_j,
//     b_{B_j} = 1/2 (x_{B_{j+1}} - x_{B_{j-1}})^perp        (eq. 4.6)
// and b = 0 elsewhere, then solve K [u v] = b and read u, v at the patch vertices
// only: an exact subset solve (support = boundary loop, wanted = patch vertices)
// on the prefactored global system, both coordinates in lanes 0 and 1 of one
// 8-lane solve. The values equal the full solve's at the patch vertices.
//
// Choices made here (the thesis leaves them open):
//  * Layout: the boundary loop on a circle whose circumference is the loop's
//    length in space, vertex B_j at the arc-length angle 2 pi s_j / S (s_j the
//    length of the loop up to B_j), counter-clockwise in the loop's order. The
//    loop follows its faces' orientation (mesh_topology boundary_loops), so the
//    parameterization keeps the faces counter-clockwise.
//  * perp rotates clockwise, (a, b)^perp = (b, -a): for a counter-clockwise loop
//    that is the outward normal, the sign for which eq. 4.6 is the Neumann data of
//    the identity map of a planar disk (K x = boundary integral of dx/dn phi_i).
//    The opposite sign only rotates the result by 180 degrees.
//  * Several boundary loops (a patch with holes, or an annulus on a torus): the
//    longest loop (arc length) carries the Neumann data, the others none.
//  * Normalization: uv is centered at the mean of the patch vertices and scaled so
//    that the farthest patch vertex is at distance 1 (the patch fits the unit disk).
//  * Flips: the signed uv area of every patch face against the majority sign;
//    faces with |area| <= 1e-12 * (mean |area|) count as degenerate, not flipped.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"

namespace locus {

// Length in space of a closed loop of vertices of m.
double loop_length(const Mesh& m, std::span<const int32_t> loop);
// Index of the longest of the loops (length in space; ties keep the first):
// the loop that carries the boundary data of a patch.
size_t longest_loop(const Mesh& m, const std::vector<std::vector<int32_t>>& loops);
// Arc-length layout of a closed loop on a circle whose circumference is the
// loop's length: xy[2j], xy[2j+1] for loop[j], counter-clockwise in loop order.
// BadInput for < 3 vertices or a loop of zero / non-finite length.
std::vector<double> circle_layout(const Mesh& m, std::span<const int32_t> loop);

// Eq. 4.6 for a closed loop of vertices of m (loop order, >= 3 distinct
// vertices): b[2j], b[2j+1] = Neumann data (u, v) at loop[j].
std::vector<double> circle_neumann_rhs(const Mesh& m, std::span<const int32_t> loop);

struct UvFlips {
  int64_t flipped = 0;     // faces whose uv orientation is against the majority
  int64_t degenerate = 0;  // faces with (numerically) zero uv area
  int orientation = 0;     // +1: majority counter-clockwise, -1: clockwise, 0: no faces
};
// uv: 2 * nv of the triangle mesh m, interleaved.
UvFlips count_uv_flips(const Mesh& m, std::span<const double> uv);
// Center at the mean, scale the largest radius to 1 (no-op scale if all coincide).
void normalize_uv(std::span<double> uv);

struct PatchParam {
  MeshPatch patch;                // the BFS patch (global ids, its own mesh)
  std::vector<int32_t> boundary;  // global ids of the loop carrying the Neumann data
  int32_t boundary_loops = 0;     // loops of the patch mesh
  int64_t euler_characteristic = 0;  // V - E + F of the patch mesh (1 for a disk)
  std::vector<double> uv_raw;     // 2 * patch size: the solution of K [u v] = b at the patch vertices
  std::vector<double> uv;         // the same, normalized
  UvFlips flips;
  int64_t forward_columns = 0, backward_columns = 0;  // of the subset solve plan
  double grow_s = 0, rhs_s = 0, solve_s = 0, check_s = 0;  // solve_s includes planning the subset solve
};

// Parameterizes the BFS patch of `count` vertices around `center` of g.mesh
// with F, the factor of the regularized Laplacian -L_C + eps M of the same mesh
// (mesh_operators regularized_laplacian). Throws BadUsage when F does not fit the
// mesh and BadInput when the patch has no boundary (the whole closed component).
PatchParam parameterize_patch(const NumericFactor& F, const PatchGrower& g, int32_t center, int32_t count,
                              PatchWorkspace& pws, SolveWorkspace& ws);

// The localized solve alone, for callers with their own patch and data:
// uv[2k], uv[2k+1] = (u, v) at wanted[k] of K [u v] = b with b at `support`
// (b[2j], b[2j+1] at support[j]). Returns the plan's column counts in `plan_out`
// when given.
void solve_patch_uv(const NumericFactor& F, std::span<const int32_t> support, std::span<const double> b,
                    std::span<const int32_t> wanted, std::span<double> uv, SolveWorkspace& ws,
                    SolvePlan* plan_out = nullptr);

}  // namespace locus
