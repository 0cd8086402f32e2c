// `nncoords` as every front end runs it (engine/include/locus/engine/
// nncoords_request.hpp): the heat Voronoi cells of the sites (thesis §3.4,
// eq. 3.18) from the Session's cached heat operator M - tL, then the
// area-stealing coordinates of the point (§3.7.2;
// pipelines/.../voronoi/natural_neighbor.hpp).
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "command_clock.hpp"
#include "field_copy.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/nncoords_request.hpp"
#include "locus/error.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {
namespace session_detail {
namespace {

using command_clock::seconds;

}  // namespace
}  // namespace session_detail

using namespace session_detail;

void check_request(const NncoordsRequest& req) {
  if (req.sites.empty()) fail(ErrorCode::BadUsage, "--sites is required (comma-separated vertex ids)");
  for (size_t k = 0; k < req.sites.size(); ++k)
    if (req.sites[k] < 0)
      fail(ErrorCode::BadUsage, "sites entry " + std::to_string(k) + " is " + std::to_string(req.sites[k]) +
                                    ", not a vertex id");
  if (req.point.face < 0) fail(ErrorCode::BadUsage, "--point is required (FACE,B0,B1,B2)");
  parse_heat_time(req.t, "--t");
}

NncoordsReport Session::nncoords(const NncoordsRequest& req, const RunContext& ctx) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  const Mesh& mesh = s->mesh;
  std::vector<SurfacePoint> sites;
  for (size_t k = 0; k < req.sites.size(); ++k) {
    if (req.sites[k] >= mesh.num_vertices())
      fail(ErrorCode::BadUsage, "sites entry " + std::to_string(k) + " is vertex " + std::to_string(req.sites[k]) +
                                    ", but the mesh has " + std::to_string(mesh.num_vertices()) + " vertices");
    sites.push_back(vertex_point(static_cast<int32_t>(req.sites[k])));
  }
  if (req.point.face >= mesh.num_faces())
    fail(ErrorCode::BadUsage, "--point: face " + std::to_string(req.point.face) + " does not exist (" +
                                  std::to_string(mesh.num_faces()) + " faces)");
  const SurfacePoint q{static_cast<int32_t>(req.point.face), -1, req.point.bary};
  check_surface_point(mesh, q, "--point", 0);
  const HeatTime time = parse_heat_time(req.t, "--t");
  const HeatQuery hq = time.times_h2 ? HeatQuery{time.value, 0.0} : HeatQuery{1.0, time.value};
  NncoordsReport r;
  const CallProgress progress(ctx, !diffusion_cached(*s, hq));
  auto t0 = std::chrono::steady_clock::now();
  const std::shared_ptr<const HeatDiffusion> H = diffusion(*s, hq, progress.build());
  const NaturalNeighborField F = locus::prepare_natural_neighbors(*H, mesh, sites, progress.query());
  r.prepare_s = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  const NaturalCoordinates c = locus::natural_neighbor_coordinates(F, mesh, q);
  r.query_s = seconds(t0);
  r.t = H->t;
  r.weights = c.weight;
  for (size_t k = 0; k < sites.size(); ++k)
    if (c.weight[k] > 0) r.natural_neighbors.push_back(static_cast<int32_t>(req.sites[k]));
  LOCUS_COPY_FIELDS(r, c, cell_area, at_site, degenerate, clamped, fallback_faces);
  progress.finish("natural-neighbor coordinates");
  return r;
}

}  // namespace locus
