// The request and report of the `voronoi` command: the heat-diffusion
// Voronoi diagram of a set of generators (thesis §3.4, eqs. 3.15-3.21), as
// every front end runs it: the CLI (`locus voronoi`),
// locus::Session::voronoi(const VoronoiCommandRequest&), the C API
// (locus_voronoi_options in locus_commands.h) and Python
// (Session.voronoi_command). Each field is one option, named as the CLI's
// long option, with the CLI's default; the checks and the call sequence live
// once, in engine/src/session_voronoi_command.cpp. The command factors its
// own M - tL (the request's cache files; the statistics are the
// factorization's); Session::voronoi(generators, ...) is the cached tier.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

// Generators: vertex ids (`sites`) or `random` seeded random surface points
// (uniform by area, splitmix64 from `seed`); exactly one of the two.
struct LOCUS_API VoronoiCommandRequest {
  std::vector<int64_t> sites;
  int32_t random = 0;     // 1..100000000 when given
  std::string t = "h2";   // diffusion time: "h2", "4h2" (multiples of h^2) or absolute ("0.001")
  std::string save, load; // factor cache files of M - tL ("" = none)
  uint64_t seed = 1;      // of `random`
};

struct LOCUS_API VoronoiCommandReport {
  std::vector<int32_t> label;           // per vertex: the generator with the most heat (eq. 3.18)
  std::vector<double> site_xyz;         // 3 per generator: its position
  std::vector<double> points;           // 3 per diagram point
  std::vector<std::vector<int32_t>> polylines;  // point ids
  int64_t segments = 0, corners = 0;
  int32_t batches = 0;                  // heat solves of 8 generators
  int64_t empty_cells = 0;              // generators labelling no vertex
  int64_t vertices_without_heat = 0;    // the heat underflowed there (raise t)
  int64_t values_solved_again = 0;
  int32_t n = 0;
  double h = 0, t = 0;
  double operator_s = 0, order_s = 0, analyze_s = 0, factor_s = 0, prepare_s = 0, solve_s = 0, diagram_s = 0;
  FactorCacheReport factor_cache;
};

// Argument checks that need no mesh: Error(BadUsage).
LOCUS_API void check_request(const VoronoiCommandRequest& req);

}  // namespace locus
LOCUS_API_END
