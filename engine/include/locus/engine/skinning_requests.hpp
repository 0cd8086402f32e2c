// The request and report of skinning weights (thesis §3.7.2, Fig. 3.12;
// pipelines/include/locus/pipelines/voronoi/skinning_weights.hpp) as every front
// end runs them: the CLI (`locus skinweights`), locus::Session::skinning, the C
// API (locus_skinweights_options in locus_commands.h) and Python (Session.skinning). Each
// field is one option, named as the CLI's long option with '-' replaced by '_',
// with the CLI's default; validation, defaults and the call sequence live once,
// in engine/src/session_skinning_command.cpp.
//
// Handles: `handles` are vertex sets (one vertex each on the CLI's
// `--handles 4530,7448`; several joined by '+', `--handles 10+11+12,40`), then
// every `bone` entry is one more handle, a polyline x0,y0,z0,x1,y1,z1,... whose
// handle is the vertices nearest to it (pipelines/.../skinning_handles.hpp).
// Columns of the weights follow that order: handles first, then bones.
// Diffusion time `t`: "" = h2 (h the mean edge length), "Ch2", or absolute.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API SkinningRequest {
  std::vector<std::vector<int64_t>> handles;  // vertex sets, 0-based ids
  std::vector<std::vector<double>> bone;      // bones: polylines, 3 coordinates per point, >= 2 points
  bool exact = false;                         // natural-neighbor coordinates at every vertex (slow)
  int32_t samples = 0;                        // sampled method: at most this many exact rows; 0 = 1024
  std::string t;                              // diffusion time; "" = h2
};

struct LOCUS_API SkinningReport {
  int32_t handles = 0;
  std::vector<double> weight;  // nv * handles, row-major: vertex v's weights at [v * handles, (v + 1) * handles)
  std::vector<std::vector<int32_t>> handle_vertices;  // per handle, its vertices (ascending)
  std::string method;          // "sampled", "coarse" (sampled on a coarse level of a large mesh) or "exact"
  int32_t samples = 0;         // vertices whose row is exact
  int32_t sample_rings = 0;    // sampled: every vertex is within this many edges of a sample
  double radius = 0;           // sampled: propagation radius (length units)
  int32_t coarse_vertices = 0; // coarse: vertices of the coarse level (0 otherwise)
  int64_t degenerate_vertices = 0;
  int64_t fallback_faces = 0;
  double max_clamped = 0;
  double t = 0;
  double factor_s = 0, prepare_s = 0, weights_s = 0, propagate_s = 0;
};

}  // namespace locus
LOCUS_API_END
