// Region-of-interest mesh deformation with a factor-once submesh factor
// (thesis §5.1 eqs. 5.1–5.3, §5.7; Botsch & Sorkine's linear variational
// deformation with the Laplacian or bi-Laplacian energy).
//
// The global operator A of the whole mesh is factored once. A region of
// interest (ROI, a BFS patch around a seed) is chosen; inside it a handle (a
// vertex and its k-ring) is moved by an offset; everything outside the ROI is
// fixed at rest. The free vertices F = ROI \ handle solve, per coordinate,
//     E_FF d_F = -E_FB d_B                                          (eq. 5.3)
// for the displacements d = x - rest, where B = handle ∪ outside holds the
// known ones (offset on the handle, 0 outside). The factor of A_FF is
// built from the global factor by the factor-once update
// (kernels/include/locus/kernels/update/factor_update.hpp), never from scratch; moving the handle again only
// re-solves (x, y, z ride in 3 of the 8 lanes of solve8).
//
// Energies (E: the energy of the thesis; A: the matrix that is factored, SPD):
//   laplacian:   E = -L_C,             A = -L_C + eps M
//   bilaplacian: E = L_C M^{-1} L_C,   A = K M^{-1} K with K = -L_C + eps M
//                                        (= E + 2 eps (-L_C) + eps^2 M)
// with eps = rel * trace(-L_C) / trace(M) as in regularized_laplacian. The
// regularization is only what makes the global (Neumann) operator
// factorizable; with the Dirichlet conditions of the ROI the exact E_FF is SPD,
// and the pipeline solves the exact system by iterative refinement with the
// factor of A_FF (x += A_FF^{-1} (b - E_FF x)), which contracts by about
// rel * (ROI diameter / edge length)^2 per step. So the result does not depend
// on the regularization, and translating the handle together with everything
// outside moves every vertex by exactly that translation (E 1 = 0).
// DeformSolveStats::residual is that of the exact system.
#pragma once
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "locus/kernels/update/factor_update.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

enum class DeformEnergy { Laplacian, Bilaplacian };
// "laplacian" | "bilaplacian"; Error(BadUsage) otherwise.
DeformEnergy parse_deform_energy(std::string_view name);
const char* deform_energy_name(DeformEnergy e);

// The factored matrix A and the exact energy E, on the same lower CSC pattern.
struct DeformMatrices {
  CscMatrix A, E;
  double eps = 0;  // absolute regularization weight
};
// Needs a triangle mesh without degenerate faces (the cotan operators' own checks).
DeformMatrices deform_matrices(const Mesh& m, DeformEnergy energy, double rel = 1e-6);

// Prepared once per mesh and energy: A, E and the global factor L of A.
struct DeformOperator {
  DeformEnergy energy = DeformEnergy::Laplacian;
  DeformMatrices mats;
  NumericFactor L;
  double operator_s = 0, order_s = 0, analyze_s = 0, factor_s = 0;  // seconds
};
DeformOperator prepare_deform_operator(const Mesh& m, DeformEnergy energy, double rel = 1e-6,
                                       const RunContext& ctx = {});

struct DeformRegion {
  std::vector<int32_t> roi;     // sorted
  std::vector<int32_t> handle;  // sorted, subset of roi
  std::vector<int32_t> free;    // sorted, roi \ handle
};
// ROI = the first round(fraction * nv) vertices of the BFS from the seed
// (kernels/include/locus/kernels/mesh/patch_grower.hpp, Rings mode); handle = vertices within
// `handle_ring` edges of `handle_vertex` that lie in the ROI. Error(BadUsage)
// for ids out of range, a fraction outside (0, 1], a handle vertex outside the
// ROI, or no free vertex left.
DeformRegion make_deform_region(const Adjacency& adj, int32_t roi_seed, double roi_fraction, int32_t handle_vertex,
                                int32_t handle_ring);

// Prepared once per region: the factor of A_FF (by the factor-once update),
// E_FF and the coupling E_FB to the known vertices.
struct DeformSystem {
  FactorUpdate sub;                    // factor of A_FF; sub.vertices = region.free
  CscMatrix E_FF;                      // local numbering of sub.vertices
  std::vector<int64_t> coupling_ptr;   // |F| + 1: E(f, b) for b not free, CSR by free local index
  std::vector<int32_t> coupling_vertex;
  std::vector<double> coupling_value;
  double update_s = 0;                 // seconds in update_factor (the rest is E_FF and the coupling)
};
DeformSystem prepare_deform_system(const DeformOperator& op, const DeformRegion& region, const RunContext& ctx = {});

struct DeformSolveStats {
  int refinement_steps = 0;     // corrections after the first solve
  double last_correction = 0;   // max-norm of the last correction / max-norm of x_F
  double residual = 0;          // ||E_FF x_F + E_FB x_B|| / ||E_FB x_B|| (worst coordinate)
};

// Deformed positions (Botsch–Sorkine: the energy is minimised by the
// displacement d = x - rest, so a zero offset keeps the rest shape and its
// details). `target` gives the wanted positions of the known vertices
// (handle and outside the ROI; entries of free vertices are ignored): their
// displacements d_B = target_B - rest_B are the Dirichlet data, the free
// displacements solve E_FF d_F = -E_FB d_B. In `out`, known vertices are copied
// from `target` bit for bit and free vertices are rest + d_F. `factor_FF` is a
// factor of A_FF in the local numbering of sys.sub.vertices — sys.sub.factor,
// or any other (e.g. from scratch, to compare). Throws Error(Numerical) when
// the refinement does not converge (free vertices that touch no known vertex,
// or a regularization too large for the region).
DeformSolveStats solve_deformation(const NumericFactor& factor_FF, const DeformSystem& sys, const Mesh& rest,
                                   const Mesh& target, Mesh& out);
// The usual target: `rest` with the handle moved by `offset`.
Mesh handle_target(const Mesh& rest, const DeformRegion& region, const std::array<double, 3>& offset);

}  // namespace locus
