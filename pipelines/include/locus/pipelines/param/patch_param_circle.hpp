// Harmonic map of a disk-like surface patch with its boundary FIXED on a circle
// (Dirichlet data, Floater/Eck: the classical harmonic parameterization), with
// the patch's factor taken from the global factor by the factor-once update
// (thesis chapter 5: "changing boundary conditions for mesh deformation or
// parameterization can be incorporated without the need of an expensive
// refactorization").
//
// Why a second patch method next to pipelines/patch_param (eq. 4.6, Neumann
// data on the global system): the Neumann route must solve through the top
// separators of the whole mesh, whose dense blocks grow with the mesh, so on a
// 1.66M-vertex mesh a 2k-vertex patch costs about what refactoring the patch
// costs; and the global system lets the boundary drift, which folds triangles
// at the boundary (11-114 flips on armadillo patches). Fixing the boundary on a
// circle gives the harmonic map with convex boundary; the factor of the
// interior block K_II comes from the update, whose work depends on the patch
// only, and the solve runs on that small factor.
//
// The problem. K = -L_C + eps M is the global operator (mesh_operators
// regularized_laplacian) factored once. B = the patch's boundary loop, laid out
// on a circle of the loop's circumference at arc-length angles (patch_param.hpp
// circle_layout);
// I = the other patch vertices. Every vertex of I has all its neighbors in the
// patch, so the rows of K_II and K_IB are the patch's own equations and
//     (-L_C)_II x_I = -(-L_C)_IB x_B        (the harmonic map, u and v)
// is exact for the patch. The factor is of K_II = (-L_C)_II + eps M_I; the
// regularization (eps M_I = K's row sums, to which -L_C's rows add nothing) is
// removed by conjugate gradients preconditioned with that factor (a few steps:
// at the default eps the screened map differs from the harmonic one by a few
// percent on a 10k-vertex patch, too much to ignore).
//
// Disk-like patches. A BFS patch can enclose holes (an unvisited vertex or a
// pocket of the last ring); their vertices would have neighbors outside the
// system. Holes are filled: the mesh vertices enclosed by a non-outer boundary
// loop (reached from it without crossing the patch and without touching the
// outside of the outer loop) join the patch. A patch that stays non-disk-like
// (a hole reaching the outside, e.g. around a handle) is refused with BadInput
// naming the center; pipelines/patch_param handles any patch.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/update/factor_update.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/pipelines/param/patch_param.hpp"

namespace locus {

struct DiskPatch {
  MeshPatch patch;                // after hole filling (patch.rings: BFS depth of the grown part)
  std::vector<int32_t> boundary;        // global ids of the outer loop, in the patch mesh's loop order
  std::vector<int32_t> boundary_local;  // the same loop as patch-mesh vertex indices
  int32_t holes_filled = 0;       // non-outer loops closed by adding the enclosed vertices
  int32_t vertices_added = 0;     // vertices those holes held
  int64_t euler_characteristic = 0;  // of the final patch mesh (1 for a disk)
};

// Per-thread scratch (n-sized maps, all -1 between calls).
struct DiskPatchWorkspace {
  PatchWorkspace grow;
  std::vector<int32_t> mark;
};

// The BFS patch of `count` vertices around `center` with its holes filled.
// Throws BadInput when the patch has no boundary (a whole closed component) or
// remains non-disk-like after filling (several loops).
DiskPatch grow_disk_patch(const PatchGrower& g, int32_t center, int32_t count, DiskPatchWorkspace& ws);

// The Dirichlet system of a disk patch, whatever factors K_II.
struct CircleDirichletSystem {
  std::vector<int32_t> interior;     // I: sorted global ids (local index a = interior[a])
  std::vector<double> rhs;           // 2 |I|: -K_IB x_B for u and v, interleaved
  std::vector<double> mass;          // |I|: eps M_ii, the row sums of K
  std::vector<double> boundary_uv;   // 2 |B|: the circle positions of patch.boundary
};
// K: the regularized Laplacian of g.mesh (lower CSC). Cost O(patch's entries of K).
CircleDirichletSystem circle_dirichlet_system(const CscMatrix& K, const DiskPatch& p, DiskPatchWorkspace& ws);

// The harmonic map's interior values from F, a factor of K_II (local
// numbering of sys.interior: as the update returns it, or a factorization of
// principal_submatrix(K, interior)), and K_II itself: x0 = K_II^-1 b, then
// conjugate gradients on (K_II - eps M_I) x = b preconditioned by F until a
// step changes x by < 1e-10 of its size (the error left is ~1e-12: each
// step gains a factor ~100). uv_interior: 2 |I|. Returns the
// refinement steps taken.
int solve_circle_dirichlet(const NumericFactor& F, const CscMatrix& K_II, const CircleDirichletSystem& sys,
                           std::span<double> uv_interior, std::span<double> work = {});

// uv of every patch vertex (patch order) from the interior solution and the circle.
std::vector<double> assemble_patch_uv(const DiskPatch& p, const CircleDirichletSystem& sys,
                                      std::span<const double> uv_interior);

struct CirclePatchParam {
  DiskPatch disk;
  std::vector<double> uv_raw;  // 2 * patch size: the harmonic map (circle radius = loop length / 2 pi)
  std::vector<double> uv;      // the same, normalized (normalize_uv)
  UvFlips flips;
  int32_t interior = 0;
  int refinement_steps = 0;
  FactorUpdateStats update;
  double grow_s = 0, system_s = 0, update_s = 0, solve_s = 0, check_s = 0;
};

// Holds the updater of one global factor: construct once (O(structure of L)),
// parameterize many patches. F and K (and the grower's mesh) must outlive it;
// one thread at a time (the updater's maps are shared between calls).
class CirclePatchParameterizer {
 public:
  CirclePatchParameterizer(const NumericFactor& F, const CscMatrix& K, const PatchGrower& g);
  CirclePatchParam parameterize(int32_t center, int32_t count, const RunContext& ctx = {});

 private:
  const PatchGrower& g_;
  const CscMatrix& K_;
  FactorUpdater updater_;
  DiskPatchWorkspace ws_;
};

}  // namespace locus
