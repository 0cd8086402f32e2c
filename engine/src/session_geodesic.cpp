// Multi-source heat geodesic distance through the Session (thesis §6.4.1, Crane et al. 2013 §3.2 "the heat method applies to any
// source set").
//
// The heat step's right-hand side is the hat functions of every source at once
// (a vertex: e_v; a point in a face: its barycentric weights on the corners, as
// the diffusion pipelines place their sources, kernels/heat/surface_point), so
// one solve of M - tL and one Poisson solve serve the whole set, on the
// Session's cached heat-method factors. The Poisson solution phi is a distance
// up to one constant per connected component; the constant is chosen so that
// the smallest value over the component's sources (phi interpolated
// barycentrically at points in faces) is 0, which keeps every distance >= 0 at
// the sources (each source's exact distance is 0; the heat method misses that by
// its smoothing error, a few percent of an edge at t = h^2). Components without
// a source get NaN (no value), as single-source queries do.
#include <cmath>
#include <limits>
#include <string>

#include "locus/kernels/solve/solve_full.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {

using namespace session_detail;

void Session::geodesic_distance(ConstView<MeshPoint> sources, View<double> out, const HeatQuery& q,
                                const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  const int32_t n = impl_->nv;
  if (sources.empty()) fail(ErrorCode::BadUsage, "geodesic_distance: no source given");
  if (out.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "geodesic_distance: output has " + std::to_string(out.size()) + " entries, expected " +
                                  std::to_string(n));
  const std::vector<SurfacePoint> pts = surface_points(*s, sources, "geodesic_distance: source");
  if (s->polygons && !s->robust) return polygon_geodesic(*s, pts, out, q, ctx);  // session_polygon.cpp
  const CallProgress progress(ctx, !geodesic_engine_cached(*s, q));
  const auto e = geodesic_engine(*s, q, progress.build());
  ctx.check_cancel();
  const HeatGeodesic& g = *e;
  std::vector<double> h(static_cast<size_t>(n), 0.0);
  for (const SurfacePoint& p : pts) {
    int32_t v[3];
    double w[3];
    const int k = surface_point_support(s->mesh, p, v, w);
    for (int c = 0; c < k; ++c) h[v[c]] += w[c];
  }
  std::vector<double> work(solve_work_size(g.heat_factor(), 1));
  solve(g.heat_factor(), h, work);
  ctx.check_cancel();
  HeatGeodesicWorkspace ws;
  g.potential_from_heat_full(h, ws);
  const HostVector<double>& phi = ws.b;
  // Per component: the minimum of phi over its sources.
  const HostVector<int32_t>& comp = s->derived->component;
  std::vector<double> shift(static_cast<size_t>(s->derived->components), std::numeric_limits<double>::infinity());
  for (const SurfacePoint& p : pts) {
    int32_t v[3];
    double w[3];
    const int k = surface_point_support(s->mesh, p, v, w);
    double value = 0;
    for (int c = 0; c < k; ++c) value += w[c] * phi[v[c]];
    double& m = shift[comp[v[0]]];
    m = std::min(m, value);
  }
  for (int32_t i = 0; i < n; ++i) {
    const double m = shift[comp[i]];
    if (std::isinf(m)) {
      out[i] = std::numeric_limits<double>::quiet_NaN();  // no source in this component: no value
      continue;
    }
    out[i] = phi[i] - m;
    if (std::isnan(out[i]))
      fail(ErrorCode::Numerical, "geodesic_distance: the distance from the source set is NaN at vertex " +
                                     std::to_string(i) + " (t = " + std::to_string(g.time()) + ")");
  }
  progress.finish("geodesic distance");
}

std::vector<double> Session::geodesic_distance(ConstView<MeshPoint> sources, const HeatQuery& q,
                                               const RunContext& ctx) const {
  std::vector<double> d(static_cast<size_t>(impl_->nv));
  geodesic_distance(sources, View<double>(d), q, ctx);
  return d;
}

std::vector<double> Session::geodesic_distance_from_vertices(ConstView<int32_t> sources, const HeatQuery& q,
                                                             const RunContext& ctx) const {
  std::vector<MeshPoint> pts;
  pts.reserve(sources.size());
  for (int32_t v : sources) pts.push_back(MeshPoint::at_vertex(v));
  return geodesic_distance(ConstView<MeshPoint>(pts), q, ctx);
}

}  // namespace locus
