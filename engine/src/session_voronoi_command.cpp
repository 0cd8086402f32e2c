// `voronoi` as every front end runs it (engine/include/locus/engine/
// voronoi_request.hpp): one factorization of M - tL (the Session's operator,
// cotan or robust; the command's own factor, through the factor cache: label
// "heat" with the resolved t, so a file of `locus factor --matrix heat`,
// `cvt` or `voronoi` with the same t loads in any of them), the heat of 8 generators per solve, vertex labels by the
// hottest generator (thesis §3.4, pipelines/.../voronoi/heat_voronoi.hpp)
// and the diagram's curves.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <string>

#include "command_clock.hpp"
#include "command_heat_operator.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/voronoi_request.hpp"
#include "locus/error.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "locus/session.hpp"

namespace locus {
using command_clock::seconds;

void check_request(const VoronoiCommandRequest& req) {
  if (req.sites.empty() == (req.random <= 0)) fail(ErrorCode::BadUsage, "give either --sites or --random N (N > 0)");
  for (int64_t v : req.sites)
    if (v < 0) fail(ErrorCode::BadUsage, "--sites: vertex " + std::to_string(v) + " is negative (ids are 0-based)");
  if (req.random > 100000000)
    fail(ErrorCode::BadUsage, "--random must be in 1..100000000 (got " + std::to_string(req.random) + ")");
  parse_heat_time(req.t, "--t");
  check_factor_cache_files({req.save, req.load});
}

VoronoiCommandReport Session::voronoi(const VoronoiCommandRequest& req, const RunContext& ctx) const {
  check_request(req);
  const Mesh mesh = this->mesh();
  std::vector<SurfacePoint> sites;
  for (int64_t v : req.sites) {
    if (v >= mesh.num_vertices())
      fail(ErrorCode::BadUsage, "--sites: vertex " + std::to_string(v) + " is not a vertex of " + mesh_name(mesh) +
                                    " (" + std::to_string(mesh.num_vertices()) + " vertices)");
    sites.push_back(vertex_point(static_cast<int32_t>(v)));
  }
  ctx.check_cancel();
  VoronoiCommandReport r;
  auto t0 = std::chrono::steady_clock::now();
  const HeatDiffusion H =
      command_heat_operator(mesh, operator_report().robust, parse_heat_time(req.t, "--t"), {req.save, req.load},
                       ctx, r.factor_cache);
  r.prepare_s = seconds(t0);
  if (req.random > 0) sites = random_surface_points(mesh, req.random, req.seed);
  if (static_cast<int64_t>(sites.size()) > mesh.num_vertices())
    fail(ErrorCode::BadInput, "more generators than vertices");
  ctx.check_cancel();
  t0 = std::chrono::steady_clock::now();
  const HeatVoronoi V = heat_voronoi(H, mesh, sites, {}, {}, ctx);
  r.solve_s = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  VoronoiDiagram D = extract_voronoi_diagram(H, mesh, sites, V, ctx);
  r.diagram_s = seconds(t0);
  std::vector<int64_t> cell_size(sites.size(), 0);
  for (int32_t l : V.label) ++cell_size[l];
  r.empty_cells = std::count(cell_size.begin(), cell_size.end(), 0);
  // Heat decays like exp(-r / sqrt(t)) and underflows to 0 far from every
  // generator (small t, few generators); such vertices are labelled by the
  // smallest generator id, which makes noisy cells: counted, so t can be raised.
  for (int32_t v = 0; v < mesh.num_vertices(); ++v)
    r.vertices_without_heat += !(V.top_value[static_cast<size_t>(v) * kVoronoiTopK] > 0);
  r.label.assign(V.label.begin(), V.label.end());
  for (const SurfacePoint& p : sites) {
    const std::array<double, 3> x = surface_point_position(mesh, p);
    r.site_xyz.insert(r.site_xyz.end(), x.begin(), x.end());
  }
  r.points = std::move(D.points);
  r.polylines = std::move(D.polylines);
  r.segments = static_cast<int64_t>(D.segments.size() / 2);
  r.corners = D.corners;
  r.batches = V.batches;
  r.values_solved_again = D.resolved_missing;
  r.n = mesh.num_vertices();
  r.h = H.h, r.t = H.t;
  r.operator_s = H.operator_s, r.order_s = H.order_s, r.analyze_s = H.analyze_s, r.factor_s = H.factor_s;
  return r;
}

}  // namespace locus
