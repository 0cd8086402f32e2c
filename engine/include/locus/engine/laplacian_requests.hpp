// The requests and reports of the chapter-2 commands `perfect-laplacian`
// (Algorithm 1) and `selfsupport` (thesis §2.6, eq. 2.12), as every front end
// runs them: the CLI, locus::Session::perfect_laplacian / self_supporting
// (the overloads taking these requests), the C API (locus_perfect_laplacian_
// options, locus_selfsupport_options in locus.h) and Python
// (Session.perfect_laplacian_command, Session.selfsupport). Each field is one
// option, named as the CLI's long option, with the CLI's default; the checks
// and the call sequence live once, in engine/src/session_laplacian_commands.cpp.
// Both run on the faces as given (a polygon mesh keeps its polygons).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct PerfectLaplacianCommandRequest {
  bool planar = false;             // use x, y (one boundary loop, held in convex position)
  int32_t iters = 1000;            // iteration cap, 1..1000000
  double eps = 1e-6;               // stop when no vertex moves more than eps * bbox diagonal
  std::string method = "newton";   // newton (interior-point Newton on the concave dual) or multiplicative (eq. 2.8)
  int32_t anderson = 6;            // multiplicative: Anderson acceleration depth, 0..50
  bool no_active_set = false;      // keep iterating every weight (thesis §2.3.3 off)
  double noise = 0;                // >= 0: seeded uniform noise of up to noise * h per coordinate first (§2.5)
  uint64_t seed = 1;               // of the noise
};

struct PerfectLaplacianCommandReport {
  std::vector<double> xyz;         // 3 * nv: the embedding (planar) or the embedding aligned onto the input
  std::vector<int32_t> edges;      // 2 per unique edge of the faces (v0 < v1)
  std::vector<double> weights;     // per edge, unit 2-norm; 0 where a weight decayed
  std::string mode;                // "planar" or "space"
  bool boundary_on_circle = false;
  int32_t boundary_loops = 0, pinned_vertices = 0;
  bool converged = false;
  int32_t iterations = 0;
  double last_change_rel = 0, min_weight = 0, min_positive_weight = 0;
  int64_t zero_weights = 0, weights_at_floor = 0, weights_revived = 0;
  int32_t kkt_rounds = 0;
  double kkt_violation = 0;
  double max_displacement_rel = 0, mean_displacement_rel = 0, align_scale = 1;
  int64_t factorizations = 0, hessian_products = 0;
  double order_s = 0, analyze_s = 0, first_iter_s = 0, iter_s = 0, rhs_s = 0, total_s = 0;
};

struct SelfSupportCommandRequest {
  std::string support = "boundary";  // supported vertices: boundary (the only choice)
  double load_density = 1.0;         // dead load per unit area (> 0)
  int32_t iters = 1000;
  double eps = 1e-6;
};

struct SelfSupportCommandReport {
  std::vector<double> xyz;           // 3 * nv: the equilibrium surface
  std::vector<int32_t> edges;        // 2 per unique edge (v0 < v1)
  std::vector<double> forces;        // per edge, >= 0, in load units
  bool converged = false;
  int32_t iterations = 0;
  double residual_rel = 0, min_force = 0, max_force = 0;
  int64_t zero_forces = 0;
  double max_displacement_rel = 0, mean_displacement_rel = 0;
  double first_iter_s = 0, iter_s = 0, total_s = 0;
};

// Argument checks that need no mesh: Error(BadUsage).
void check_request(const PerfectLaplacianCommandRequest& req);
void check_request(const SelfSupportCommandRequest& req);

}  // namespace locus
LOCUS_API_END
