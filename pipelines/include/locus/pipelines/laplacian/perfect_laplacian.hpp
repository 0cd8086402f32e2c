// Perfect Laplacians for polygon meshes: Algorithm 1 of thesis chapter 2
// (§2.3.1 planar meshes, eqs. 2.4-2.8; §2.3.2 meshes in space, eqs. 2.9-2.10;
// §2.3.3 steady state, eq. 2.11).
//
// Start with ω = 1 on every unique edge of the faces; repeat: embed the mesh by
// solving the embedding system (kernels/include/locus/kernels/mesh/polygon_laplacian.hpp), multiply each
// weight by (embedded length / target length) (eq. 2.8), normalize to unit 2-norm;
// stop when no vertex moved more than eps · (bounding-box diagonal of the
// embedding) in the last iteration. The pattern of the system never changes: one
// METIS ordering and one symbolic analysis, then one numeric refactorization per
// iteration.
//
// The default method (PerfectLaplacianOptions::method = newton) reaches the same
// steady state by an interior-point Newton method on the concave function whose
// KKT conditions are eq. 2.11 (pipelines/include/locus/pipelines/laplacian/perfect_laplacian_newton.hpp): each
// iteration is still one numeric refactorization of the same pattern plus solves.
// The multiplicative method is the thesis' loop as below.
//
// Generalizations of the thesis' loop, each documented where it acts:
//  * Right-hand-side scale. Normalizing ω changes nothing when b = 0 (planar
//    meshes) or when no vertex is fixed but a pin (closed meshes: the embedding
//    only scales). With fixed vertices AND b != 0 (a mesh in space with boundary,
//    self-supporting surfaces) it would change the problem, so the solve uses
//    b · rhs_scale with rhs_scale = 1 / (product of all normalization divisors):
//    the iterates are exactly those of the un-normalized update while the stored
//    weights stay O(1). The raw (un-normalized) weights are weights / rhs_scale.
//  * Residual. The update of eq. 2.8 is, in log form, the fixed-point iteration
//    U <- U + f(U), f_e = log(||e(U)|| / ||ê_e||) on U = log ω. With b = 0 the
//    embedding ignores the scale of ω and the steady state only asks the active
//    edges for a COMMON ratio μ^-1 (eq. 2.11), so the iterated residual is
//    g = f - c, c the ω²-weighted mean of f over the active edges (the first-
//    order shift the normalization applies); with b != 0 it is f itself.
//  * Active set (§2.3.3, pipelines/include/locus/pipelines/laplacian/weight_active_set.hpp). Where no perfect
//    Laplacian exists some weights decay geometrically toward their limit 0 and
//    the plain update needs hundreds to thousands of iterations to let the
//    vertices settle. An edge whose decay is established (g_e < 0 without fading
//    over a window) is pushed toward 0 by a growing extrapolation of its own
//    decay (undone if g_e turns positive; all edges of a vertex that loses every
//    edge get one common push), then dropped: its weight becomes exactly 0 and
//    it is no longer iterated. At convergence the dropped edges are checked
//    against the steady state (g_e <= kkt_tol, i.e. their length ratio does not
//    exceed the common one); violators come back and the iteration resumes.
//    Weights that fall below floor_rel · max are dropped too.
//  * Acceleration. Anderson acceleration (depth 6, kernels/include/locus/kernels/
//    optim/anderson_acceleration.hpp) of the map U <- U + g on the ACTIVE edges only,
//    restarted whenever the active set changes; it keeps every weight positive
//    by construction; a step never changes a weight by more than e^4, and the
//    history is dropped when ||g|| grows 10x over its best.
//  * Passive edges. An edge with both ends fixed enters no row of eq. 2.4: its
//    weight is not iterated and keeps its initial value.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/kernels/mesh/polygon_laplacian.hpp"
#include "locus/pipelines/laplacian/weight_active_set.hpp"

namespace locus {

// The generic problem of Algorithm 1 (also used by the parameterization and the
// self-supporting surfaces of §2.6).
struct PerfectLaplacianProblem {
  int32_t nv = 0;
  int dims = 3;                        // 2 (planar embedding) or 3
  std::vector<int32_t> e0, e1;         // unique edges of the faces
  std::vector<double> target_length;   // per edge, > 0: the lengths ||ê|| of eq. 2.8
  std::vector<uint8_t> fixed;          // per vertex: held at fixed_pos
  Coords fixed_pos;                    // nv per used coordinate (only fixed entries are read)
  Coords b;                            // right-hand side of eq. 2.10 per vertex, empty = 0
  std::vector<double> initial_weights; // empty = all 1 (Algorithm 1)
};

// How the steady state is reached: `newton` (default) maximizes the concave
// function whose KKT conditions are eq. 2.11 by projected Newton-CG
// (pipelines/include/locus/pipelines/laplacian/perfect_laplacian_newton.hpp); `multiplicative` is the update of
// eq. 2.8 with Anderson acceleration and the active set below.
enum class PerfectLaplacianMethod : uint8_t { newton, multiplicative };

struct PerfectLaplacianOptions {
  PerfectLaplacianMethod method = PerfectLaplacianMethod::newton;
  int max_iterations = 1000;
  double eps = 1e-6;            // stop when max vertex change < eps · bbox diagonal of the embedding
  int anderson_depth = 6;       // 0 = the plain update of eq. 2.8
  double relaxation = 1.0;      // the log-space step is relaxation · g (1 = eq. 2.8)
  // b = 0: residual relative to the common ratio (see above). Without it the
  // iteration stops short of the steady state (no zero weights, a spread of
  // length ratios); figures in docs/perfect_laplacian.md.
  bool center_residual = true;
  double anderson_restart = 10; // drop the history when ||f|| exceeds this · best ||f|| so far
  double max_log_step = 4.0;    // no weight changes by more than e^4 in one iteration
  double floor_rel = 1e-12;     // weights below this · max weight are exactly 0 (their limit)
  double zero_weight_rel = 1e-8;  // weights <= this · max weight count as numerically zero
  bool drop_decaying = true;    // the active set of §2.3.3 (false: every weight stays iterated)
  WeightActiveSetOptions active_set;
  int max_kkt_rounds = 10;      // convergence checks that may revive dropped edges
  EmbeddingSystemOptions system;
  // Newton (interior point, pipelines/include/locus/pipelines/laplacian/perfect_laplacian_newton.hpp): maximizes
  // Ψ + τ Σ log ω with τ = mu · (the mean ω_e ||ê_e||² scale); mu goes from
  // newton_barrier_start down to newton_barrier_end by newton_barrier_factor after
  // each full Newton step, and convergence needs the end value. A lower end
  // leaves weights a mesh needs near 0 numerically zero, a higher one slows the
  // polygon meshes; 1e-12 avoids both (docs/perfect_laplacian.md).
  double newton_barrier_start = 0.1;
  double newton_barrier_end = 1e-12;
  // With b != 0 (meshes in space) the end value is 1e-10: ratios are pinned to 1
  // and the barrier's relative error there is far below the displacement
  // targets, while 1e-12 takes far more iterations (docs/perfect_laplacian.md).
  double newton_barrier_end_rhs = 1e-10;
  double newton_barrier_factor = 0.1;
  double newton_zero_rel = 1e-10;  // weights <= this · max at the end are exactly 0 (vanished)
  // CG steps (one solve each, no factorization) per iteration: newton_cg_work /
  // (iterated edges), clamped to [newton_cg_min, newton_cg_max]. Small meshes get
  // (nearly) exact Newton steps, which the polygon meshes need to converge;
  // large ones get 10, which keeps an iteration near the cost of a factorization
  // and still converges (figures in docs/perfect_laplacian.md).
  int newton_cg_max = 100;
  int newton_cg_min = 10;
  int64_t newton_cg_work = 500000;
  double newton_forcing = 0.5;     // CG stops at relative residual min(this, sqrt(||g|| / ||g_1||))
  double newton_min_ratio = 0.05;  // a step shrinks no weight below this fraction of itself
  // Newton: halvings of the step tried before falling back to the plain step.
  int newton_line_search = 30;
};

struct PerfectLaplacianResult {
  Coords pos;                    // the embedding V of the last iteration
  std::vector<double> weights;   // normalized (unit 2-norm) weights; decayed ones are exactly 0
  double rhs_scale = 1.0;        // raw weights (those that balance b) = weights / rhs_scale
  bool converged = false;
  int iterations = 0;
  double last_change_rel = 0;    // max vertex change of the last iteration / bbox diagonal
  double min_weight = 0;         // over all edges (0 when some decayed to the floor)
  double min_positive_weight = 0;
  int64_t zero_weights = 0;      // <= zero_weight_rel · max weight
  int64_t at_floor = 0;          // weights exactly 0 (dropped by the active set)
  int64_t revived = 0;           // dropped edges brought back by a steady-state check
  int kkt_rounds = 0;            // steady-state checks that revived edges
  double kkt_violation = 0;      // max over dropped edges of g_e (<= kkt_tol when steady; 0 if none)
  bool scale_free = true;        // b = 0: residual relative to the common ratio
  double order_s = 0, analyze_s = 0;
  double first_iter_s = 0;       // the first iteration including order + analyze + factorize
  double iter_s = 0;             // median of the later iterations (refactorize, solve, update)
  std::vector<double> change_history;  // max vertex change / diagonal per iteration
  int64_t factorizations = 0;    // numeric factorizations (Newton: line-search trials included)
  int64_t hessian_products = 0;  // Newton: CG steps (one solve each)
};

PerfectLaplacianResult run_perfect_laplacian(const PerfectLaplacianProblem& problem,
                                             const PerfectLaplacianOptions& opt = {}, const RunContext& ctx = {});

// ---- Algorithm 1 on a mesh ----

struct MeshPerfectLaplacianOptions {
  // Planar mode (§2.3.1): forced by `planar` (z is ignored) or chosen when every
  // z is equal. Needs exactly one boundary loop. The boundary is held at its input
  // positions when it is (weakly) convex, otherwise on a circle (see below).
  bool planar = false;
  // In space (§2.3.2): boundary vertices are held at their input positions; a
  // component without boundary gets one pinned vertex (its lowest-numbered one):
  // with Σ_i b_i = 0 (true for the b below) pinning is exact, not a regularization.
  PerfectLaplacianOptions iteration;
};

struct MeshPerfectLaplacianResult {
  std::string mode;                  // "planar" or "space"
  bool boundary_on_circle = false;   // planar mode with a non-convex boundary
  int32_t boundary_loops = 0;
  int32_t pinned = 0;                // pins of closed components
  std::vector<int32_t> e0, e1;       // the edges the weights belong to
  PerfectLaplacianResult run;
  Coords aligned;                    // run.pos after the best similarity (scale s, translation t) onto the input
  double align_scale = 1.0;
  double max_displacement_rel = 0;   // after alignment, / bbox diagonal of the input
  double mean_displacement_rel = 0;
  double bbox_diagonal = 0;          // of the input (in the dimensions used)
  double rhs_s = 0;                  // computing H_i n_i
  double total_s = 0;
};

// Validates the mesh (manifold, no unreferenced vertices, no zero-length edge;
// BadInput naming the element otherwise) and runs Algorithm 1.
//
// H_i n_i (eq. 2.10) is the integrated mean-curvature normal of the INPUT,
// b = L_C x̂, with L_C the cotan Laplacian (kernels/mesh_operators) of the mesh,
// polygons fan-triangulated from their first vertex. It vanishes at planar
// vertices (linear precision) and Σ_i b_i = 0 exactly as for any Laplacian, which
// is what makes a single pin exact on closed meshes. For planar cyclic polygons
// (squares, rectangles, isosceles trapezoids: regular quad meshes) the fan
// diagonal's cotan weight is 0, so b is realizable on the polygon edges alone.
MeshPerfectLaplacianResult perfect_laplacian(const Mesh& m, const MeshPerfectLaplacianOptions& opt = {},
                                             const RunContext& ctx = {});

// Best similarity without rotation: s, t minimizing Σ_i ||s p_i + t - q_i||^2 over
// `dims` coordinates. Writes s·p + t into `out` and returns s.
double align_similarity(int dims, const Coords& p, const Coords& q, Coords& out);

// Integrated mean-curvature normal b = L_C x̂ of a polygon mesh (fan triangulation), see above.
Coords integrated_mean_curvature_normal(const Mesh& m);

// Helpers shared by the multiplicative and the Newton method and the mesh front
// (perfect_laplacian.cpp).
namespace perfect_laplacian_detail {
double median(std::vector<double> v);  // 0 for an empty list
// Diagonal of the bounding box of the first n points of p in `dims` coordinates.
double bbox_diagonal(int dims, const Coords& p, size_t n);
// Length of edge (a, b) of the points p in `dims` coordinates.
double edge_length(int dims, const Coords& p, int32_t a, int32_t b);
// P.target_length: the length in space of every edge (P.e0[e], P.e1[e]) of m,
// the targets when the input shape is kept (flip-free parameterization,
// self-supporting surfaces); BadInput naming the first edge of zero length
// (perfect_laplacian_mesh.cpp).
void set_target_lengths_in_space(const Mesh& m, PerfectLaplacianProblem& P);
// True when the right-hand side b is zero: the steady state then fixes the
// weights only up to scale (§2.3.3).
bool scale_free(const PerfectLaplacianProblem& P);
}  // namespace perfect_laplacian_detail

}  // namespace locus
