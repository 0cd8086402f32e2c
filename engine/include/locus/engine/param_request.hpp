// The request and report of the `param` command, as every front end runs it:
// the CLI (`locus param`), locus::Session::param, the C API
// (locus_param_options in locus.h) and Python (Session.param). Each field is
// one option, named as the CLI's long option, with the CLI's default; the
// checks and the call sequence live once, in engine/src/session_param_command.cpp.
//
// Two domains:
//  * disk (center < 0, the default): the whole mesh, a disk, polygons as
//    given; boundary on the unit circle by arc length, interior from eq. 2.4
//    with perfect (Algorithm 1: iters, eps), cotan or uniform weights
//    (thesis §2.6);
//  * patch (center >= 0): the breadth-first patch of round(fraction * nv)
//    vertices around center (thesis §4.4), from the factor of the whole
//    mesh's -L_C + eps M: boundary neumann (the Neumann data of eq. 4.6, one
//    subset solve) or circle (the boundary fixed on a circle, the interior's
//    factor by the factor-once update). save / load keep that factor.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/export.h"
#include "locus/mesh.hpp"

LOCUS_API_BEGIN
namespace locus {

struct ParamRequest {
  std::string method = "perfect";    // disk: perfect, cotan or uniform
  int32_t iters = 1000;              // disk, perfect: Algorithm 1's iteration cap (>= 1)
  double eps = 1e-6;                 // disk, perfect: Algorithm 1's tolerance (> 0)
  int64_t center = -1;               // >= 0: the patch mode around this vertex
  double fraction = 0.1;             // patch: in (0, 1]
  std::string boundary = "neumann";  // patch: neumann or circle
  std::string save, load;            // patch: factor cache files of the global factor
};

struct ParamReport {
  std::string domain;            // "disk" or "patch"
  std::vector<double> uv;        // disk: 2 per vertex; patch: 2 per patch vertex, in the unit disk
  int64_t flipped_faces = 0, degenerate_faces = 0;
  // disk
  int64_t first_flipped_face = -1;
  double min_corner_sin = 1;
  int64_t negative_weights = 0;
  double min_weight = 0;
  bool converged = true;         // perfect
  int32_t iterations = 0;
  int64_t zero_weights = 0;
  double first_iter_s = 0, iter_s = 0, param_s = 0;
  // patch
  int32_t n = 0;
  Mesh patch;                    // the patch as a mesh of its own: vertex k is patch_vertices[k]
  std::vector<int32_t> patch_vertices;  // global ids, center first
  int64_t patch_faces = 0;
  int32_t bfs_rings = 0, boundary_vertices = 0, boundary_loops = 0;
  int32_t holes_filled = 0, vertices_added = 0, interior_vertices = 0, refinement_steps = 0;  // circle
  int64_t euler_characteristic = 0;
  int32_t orientation = 0;       // +1: majority counter-clockwise, -1: clockwise
  int32_t etree_height = 0;
  int64_t forward_columns = 0, backward_columns = 0;  // neumann: the subset solve's plan
  int64_t update_supernodes = 0, update_supernodes_recomputed = 0, update_columns_recomputed = 0,
          update_values_stored = 0;  // circle: the factor-once update
  double operator_s = 0, order_s = 0, analyze_s = 0, numeric_s = 0, prepare_s = 0, query_s = 0;
  double grow_s = 0, rhs_s = 0, system_s = 0, update_s = 0, solve_s = 0, check_s = 0;
  double factor_s() const { return order_s + analyze_s + numeric_s; }
  FactorCacheReport factor_cache;
};

// Argument checks that need no mesh: Error(BadUsage).
void check_request(const ParamRequest& req);
// The faces a polygon file is read with: kept for the disk, triangulated for a patch.
bool keeps_polygons(const ParamRequest& req);

}  // namespace locus
LOCUS_API_END
