// Self-supporting surfaces (thesis §2.6, eq. 2.12) with Algorithm 1.
//
// A network of struts along the edges of a polygon mesh carries the dead load
// F_i of each vertex down to the supported vertices when, at every unsupported
// vertex i,
//     Σ_j f_ij (v_j - v_i) / ||v_j - v_i|| = (0, 0, -F_i),   f_ij >= 0,
// i.e. with ω_ij = f_ij / ||e_ij||: L_ω V = (0, 0, -F) with a non-negative
// Laplacian (compression only). That is the embedding system of Algorithm 1 in
// space with b_i = (0, 0, -F_i) and the supports held fixed, so the loop of
// pipelines/perfect_laplacian iterates heights (all coordinates, in fact) and
// weights until the network matches the input edge lengths as closely as an
// equilibrium allows. Every iterate is an exact equilibrium of its own weights
// (that is how V is computed); the residual reported is re-measured edge by
// edge, independently of the factorization. Because b != 0 and the supports are
// fixed, the scale of ω matters: the loop keeps raw weights (rhs_scale, see
// perfect_laplacian.hpp), and the forces are in the units of the load.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"

namespace locus {

struct SelfSupportOptions {
  // Supported vertices: "boundary" (every boundary loop) is the only choice so far.
  std::string support = "boundary";
  // Dead load F_i = load_density · A_i, A_i = Σ over incident faces of area / degree
  // (3-D areas of the INPUT faces, fixed during the iteration).
  double load_density = 1.0;
  PerfectLaplacianOptions iteration;
};

struct SelfSupportResult {
  Coords pos;                      // the equilibrium surface
  std::vector<int32_t> e0, e1;
  std::vector<double> forces;      // f_e = ω_e ||e|| >= 0 (raw weights), per edge
  std::vector<double> load;        // F_i per vertex (0 at supports)
  std::vector<uint8_t> supported;
  bool converged = false;
  int iterations = 0;
  double residual_rel = 0;         // max_i ||(L_ω V)_i - b_i|| / max_i F_i over unsupported i
  double min_force = 0;            // over edges with an unsupported end
  double max_force = 0;
  int64_t zero_forces = 0;         // forces <= 1e-8 · max force (edges dropped by §2.3.3)
  double max_displacement_rel = 0; // ||V - input|| / bbox diagonal (no alignment: supports fixed)
  double mean_displacement_rel = 0;
  double first_iter_s = 0, iter_s = 0, total_s = 0;
};

// Needs a manifold polygon mesh with at least one boundary loop and no
// unreferenced vertices (BadInput otherwise).
SelfSupportResult self_supporting(const Mesh& m, const SelfSupportOptions& opt = {}, const RunContext& ctx = {});

}  // namespace locus
