// The request and report of the `deform` command (thesis §5.1, §5.7), as
// every front end runs it: the CLI (`locus deform`), locus::Session::deform,
// the C API (locus_deform_options in locus.h) and Python (Session.deform).
// Each field is one option, named as the CLI's long option with '-' replaced
// by '_', with the CLI's default; validation, defaults and the call sequence
// live once, in engine/src/session_deform_command.cpp.
//
// The handle (the handle vertex and its handle_ring-ring inside the region
// of interest) moves by `offset`; the region of interest is the breadth-first
// patch of round(roi_fraction * nv) vertices around roi_seed; outside it
// nothing moves. The global operator (-L_C + eps M for the Laplacian energy,
// K M^{-1} K for the bilaplacian, eps = regularization relative to the
// operator's scale) is factored once; the factor of the free vertices' block
// comes from the factor-once update (kernels/.../factor_update.hpp).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API DeformCommandRequest {
  int64_t roi_seed = -1;                // required
  double roi_fraction = 0.1;            // in [0, 1]
  int64_t handle = -1;                  // required, inside the region of interest
  int32_t handle_ring = 1;              // in 0..1000
  std::array<double, 3> offset{0, 0, 0};  // required: the handle's displacement
  std::string energy = "laplacian";     // laplacian or bilaplacian
  double regularization = 1e-6;         // relative eps of the factored global operator (> 0)
  std::string save{}, load{};           // factor cache files of the global factor ("" = none)
};

struct LOCUS_API DeformCommandReport {
  std::vector<double> xyz;  // 3 * nv deformed positions, interleaved
  std::string energy;
  int32_t n = 0;
  int32_t roi_vertices = 0, handle_vertices = 0, free_vertices = 0;
  // The factor-once update of the free vertices' factor, and the solve.
  double columns_updated_fraction = 0;
  int64_t supernodes_recomputed = 0, supernodes = 0, values_stored_update = 0;
  int refinement_steps = 0;
  double residual = 0;          // of the exact Dirichlet system
  double max_displacement = 0;  // the largest distance a vertex moved
  // The baseline (compare_refactor): the free vertices' block ordered,
  // analyzed and factored from scratch and solved again.
  bool compared = false;
  int64_t values_stored_refactor = 0;
  double update_vs_refactor_max_diff = 0;  // largest coordinate difference of the two solutions
  // Seconds: the global operator and its factor (0 when cached or loaded),
  // the region, the update and its phases, the solve, the baseline.
  double operator_s = 0, order_s = 0, analyze_s = 0, factor_s = 0, region_s = 0;
  double update_s = 0, update_structure_s = 0, update_mark_s = 0, update_copy_s = 0, update_factor_s = 0;
  double system_s = 0, solve_s = 0, refactor_s = 0, refactor_solve_s = 0;
  FactorCacheReport factor_cache;
  std::vector<std::string> warnings;  // e.g. a mesh that is not a manifold, deformed as its manifold sheets
};

// Argument checks that need no mesh: Error(BadUsage).
LOCUS_API void check_request(const DeformCommandRequest& req);

}  // namespace locus
LOCUS_API_END
