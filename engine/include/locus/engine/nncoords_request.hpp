// The request and report of the `nncoords` command: natural-neighbor
// (area-stealing) coordinates of a surface point with respect to vertex
// sites, with heat-diffusion cells (thesis §3.7.2), as every front end runs
// it: the CLI (`locus nncoords`), locus::Session::nncoords, the C API
// (locus_nncoords_options in locus.h) and Python (Session.nncoords). Each
// field is one option, named as the CLI's long option, with the CLI's
// default; the checks and the call sequence live once, in
// engine/src/session_nncoords_command.cpp. Session::natural_neighbor_coordinates
// and prepare_natural_neighbors are the prepared tier (many points).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

// A point in a triangle of the mesh: its barycentric weights (summing to 1)
// of the triangle's corners in order.
struct FacePoint {
  int64_t face = -1;
  std::array<double, 3> bary{1.0 / 3, 1.0 / 3, 1.0 / 3};
};

struct NncoordsRequest {
  std::vector<int64_t> sites;  // vertex ids, at least one (required)
  FacePoint point;             // the query point (required: face -1 = not given)
  std::string t = "h2";        // diffusion time: "h2", "4h2" (multiples of h^2) or absolute ("0.001")
};

struct NncoordsReport {
  std::vector<double> weights;              // one per site, >= 0, summing to 1
  std::vector<int32_t> natural_neighbors;   // the sites with a nonzero weight (ids), in site order
  double cell_area = 0;                     // the point's own cell
  bool at_site = false, degenerate = false;
  double clamped = 0;                       // negative differences set to zero, relative to cell_area
  int64_t fallback_faces = 0;
  double t = 0;                             // the absolute time used
  double prepare_s = 0, query_s = 0;
};

// Argument checks that need no mesh: Error(BadUsage).
void check_request(const NncoordsRequest& req);

}  // namespace locus
LOCUS_API_END
