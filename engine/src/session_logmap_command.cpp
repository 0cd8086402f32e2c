// `logmap` as every front end runs it (engine/include/locus/engine/
// geodesic_requests.hpp): the log map of the geodesic disk of
// round(fraction * n) vertices around the center. heat: thesis §6.5-6.6 with
// exact subset solves (pipelines/.../geodesic/logmap.hpp); heat-full: the
// same with full solves; dem: the Dijkstra-based discrete exponential map
// (dem_logmap.hpp); polygon meshes: the polygon log map with full solves on
// the Dijkstra disk over the polygon edges (polygon_logmap.hpp). Then the
// map's flipped triangles and injectivity radius, and with clip_injective
// the patch cut to the vertices inside that radius.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "field_copy.hpp"
#include "locus/engine/factor_store.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/pipelines/geodesic/polygon_logmap.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"
#include "sheets_session.hpp"

namespace locus {

using namespace session_detail;

namespace session_detail {
namespace {

LogMapAngle angle_of(const std::string& s) {
  if (s == "auto") return LogMapAngle::Auto;
  if (s == "log") return LogMapAngle::LogHeat;
  if (s == "two-ring") return LogMapAngle::LogHeatTwoRing;
  if (s == "average") return LogMapAngle::HeatAverage;
  fail(ErrorCode::BadUsage, "angle must be auto, log, two-ring or average (got '" + s + "')");
}

// The estimator of a request: the library's defaults (LogMapOptions) where it says "default".
LogMapEstimator estimator_of(const LogmapRequest& req) {
  LogMapEstimator e = LogMapOptions{}.estimator();
  e.angle = angle_of(req.angle);
  if (req.lattice == "none") e.lattice = LatticeCorrection::None;
  else if (req.lattice == "star") e.lattice = LatticeCorrection::Star;
  else if (req.lattice == "ring") e.lattice = LatticeCorrection::Ring;
  else if (req.lattice == "path") e.lattice = LatticeCorrection::Path;
  else if (req.lattice != "default")
    fail(ErrorCode::BadUsage, "lattice must be none, star, ring or path (got '" + req.lattice + "')");
  if (req.recenter == "on" || req.recenter == "off") e.recenter = req.recenter == "on";
  else if (req.recenter != "default")
    fail(ErrorCode::BadUsage, "recenter must be on or off (got '" + req.recenter + "')");
  return e;
}

void resize_map(LogmapReport& r, size_t k) {
  r.distance.resize(k), r.angle.resize(k), r.u.resize(k), r.v.resize(k);
}

void polygon_map(State& s, const LogmapRequest& req, const HeatTime& time, int32_t count, LogmapReport& r,
                 const RunContext& ctx) {
  const bool given = !req.t.empty() || req.t_factor.has_value();
  const double tf = given ? heat_time_factor(time, time.times_h2 ? 0.0 : mean_edge_length(*s.polygons)) : 0.0;
  auto t0 = std::chrono::steady_clock::now();
  const auto e = polygon_engine(s, HeatQuery{tf}, ctx);  // polygon_logmap below finds it built
  r.precompute_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  const LogMapResult m = polygon_logmap(s, static_cast<int32_t>(req.center), count, HeatQuery{tf}, ctx);
  r.query_s = seconds_since(t0);
  r.patch.assign(m.patch.begin(), m.patch.end());
  r.distance.assign(m.distance.begin(), m.distance.end());
  r.angle.assign(m.angle.begin(), m.angle.end());
  r.u.assign(m.u.begin(), m.u.end());
  r.v.assign(m.v.begin(), m.v.end());
  r.polygon = true;
  r.method = "heat-full-polygon";
  r.angle_estimator = "log";
  r.t_factor = polygon_t_factor(HeatQuery{tf});
  r.t = e->geodesic().time();
  r.h = e->geodesic().mean_edge_length();
  r.flipped = count_flipped_polygons(*s.polygons, r.patch, r.u, r.v);
}

void dem_map(State& s, int32_t center, int32_t count, LogmapReport& r) {
  auto t0 = std::chrono::steady_clock::now();
  const auto dem = s.dem.get(0, RunContext{}, [&] { return std::make_shared<const DemLogMap>(s.mesh); });
  r.precompute_s = seconds_since(t0);
  DemWorkspace dws;
  r.patch.resize(static_cast<size_t>(count));
  r.u.resize(static_cast<size_t>(count));
  r.v.resize(static_cast<size_t>(count));
  t0 = std::chrono::steady_clock::now();
  const int32_t k = dem->query(center, count, std::numeric_limits<double>::infinity(), r.patch, r.u, r.v, dws);
  r.query_s = seconds_since(t0);
  r.patch.resize(static_cast<size_t>(k));
  r.u.resize(static_cast<size_t>(k));
  r.v.resize(static_cast<size_t>(k));
  for (int32_t p = 0; p < k; ++p) {
    r.distance.push_back(std::hypot(r.u[p], r.v[p]));
    r.angle.push_back(std::atan2(r.v[p], r.u[p]));
  }
  r.angle_estimator = "dem";
}

void heat_map(State& s, const LogmapRequest& req, int32_t count, LogmapReport& r, const RunContext& ctx) {
  const int32_t center = static_cast<int32_t>(req.center);
  const LogMapEstimator est = estimator_of(req);
  const CallProgress progress(ctx, req.save.size() + req.load.size() > 0 || !s.engines.contains(bits_of(r.t_factor)));
  const auto g = grower(s, ctx);
  auto t0 = std::chrono::steady_clock::now();
  const auto e = heat_method_engine(s, r.t_factor, {req.save, req.load}, r.factor_cache, progress.build());
  r.precompute_s = seconds_since(t0);  // the heat map's own preparation
  ctx.check_cancel();
  PatchWorkspace pws;
  t0 = std::chrono::steady_clock::now();
  grow_patch_vertices(*g, center, geodesic_disk(count), pws, r.patch);
  r.patch_s = seconds_since(t0);
  resize_map(r, r.patch.size());
  LogMapWorkspace ws;
  t0 = std::chrono::steady_clock::now();
  const LogMapOutput out{r.distance, r.angle, r.u, r.v};
  const LogMapStats st =
      req.method == "heat" ? e->query(center, r.patch, out, ws, est) : e->query_full(center, r.patch, out, ws, est);
  r.query_s = seconds_since(t0);
  r.heat = true;
  r.t = e->geodesic().time();
  r.h = e->geodesic().mean_edge_length();
  LOCUS_COPY_FIELDS(r, st, sources, batches, passes, two_ring, recentered, angle_fallbacks);
  r.heat_underflow_vertices = st.underflow;
  r.t_avoiding_underflow = st.t_no_underflow;
  progress.finish("log map");
}

// Flipped triangles and the injectivity radius (the largest radius with no
// flipped triangle; infinite: none flipped); with `clip`, the patch and its
// values shrunk to the vertices inside it, and the flips counted again.
void injectivity(const Mesh& mesh, bool clip, LogmapReport& r) {
  const TriangleGradients tg = triangle_gradients(mesh);
  std::vector<int32_t> scratch;
  r.flipped = count_flipped_triangles(tg, r.patch, r.u, r.v, scratch);
  r.injectivity_radius = injectivity_radius(tg, r.patch, r.u, r.v, r.distance, scratch);
  if (!clip || !std::isfinite(r.injectivity_radius)) return;
  size_t w = 0;
  for (size_t p = 0; p < r.patch.size(); ++p)
    if (r.distance[p] < r.injectivity_radius)
      r.patch[w] = r.patch[p], r.distance[w] = r.distance[p], r.angle[w] = r.angle[p], r.u[w] = r.u[p],
      r.v[w] = r.v[p], ++w;
  r.clipped_vertices = static_cast<int32_t>(r.patch.size() - w);
  r.patch.resize(w);
  resize_map(r, w);
  r.flipped = count_flipped_triangles(tg, r.patch, r.u, r.v, scratch);
}

// A mesh that is not a manifold: the map of the center's sheet (sheets_session.hpp),
// the patch of the same vertex count, mapped back to the input's vertices (a
// vertex split into copies keeps the copy nearest the center).
LogmapReport sheets_map(State& s, const LogmapRequest& req, const RunContext& ctx) {
  const std::shared_ptr<const SheetsSession> sh = sheets_session(s, ctx);
  const std::string name = mesh_name(s.mesh);
  LogmapRequest q = req;
  q.center = sheet_vertex(*sh, req.center, "center", name);
  const int32_t n = s.mesh.num_vertices(), ns = sh->sheets.mesh.num_vertices();
  const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(req.fraction * n)));
  q.fraction = std::min(1.0, static_cast<double>(count) / ns);
  LogmapReport r = sh->session->logmap(q, ctx);
  std::vector<char> seen(static_cast<size_t>(n), 0);
  size_t w = 0;
  for (size_t p = 0; p < r.patch.size(); ++p) {  // the patch is in order of distance
    const int32_t v = sh->sheets.vertex_of[r.patch[p]];
    if (seen[v]) continue;
    seen[v] = 1;
    r.patch[w] = v, r.distance[w] = r.distance[p], r.angle[w] = r.angle[p], r.u[w] = r.u[p], r.v[w] = r.v[p];
    ++w;
  }
  r.patch.resize(w);
  resize_map(r, w);
  r.center = static_cast<int32_t>(req.center);
  r.fraction = req.fraction;
  r.warnings.push_back(sh->describe("the log map", name));
  return r;
}

}  // namespace
}  // namespace session_detail

void check_request(const LogmapRequest& req) {
  check_fraction(req.fraction);
  heat_method_time(req.t, req.t_factor);
  estimator_of(req);
  if (req.method != "heat" && req.method != "heat-full" && req.method != "dem")
    fail(ErrorCode::BadUsage, "method must be heat, heat-full or dem (got '" + req.method + "')");
  check_factor_cache_files({req.save, req.load});
  if (req.method == "dem" && (!req.save.empty() || !req.load.empty()))
    fail(ErrorCode::BadUsage, "save/load: the dem method factors nothing");
}

bool keeps_polygons(const LogmapRequest& req) {
  return req.method != "dem" && req.save.empty() && req.load.empty();
}

LogmapReport Session::logmap(const LogmapRequest& req, const RunContext& ctx) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  check_vertex(*s, req.center, "center");
  if (impl_->op.robust && impl_->op.any_defect()) return sheets_map(*s, req, ctx);
  const HeatTime time = heat_method_time(req.t, req.t_factor);
  const int32_t n = impl_->nv;
  const int32_t center = static_cast<int32_t>(req.center);
  const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(req.fraction * n)));
  LogmapReport r;
  r.center = center;
  r.fraction = req.fraction;
  r.method = req.method;
  r.angle_estimator = req.angle;
  if (s->polygons && keeps_polygons(req)) {
    polygon_map(*s, req, time, count, r, ctx);
  } else {
    r.t_factor = heat_time_factor(time, time.times_h2 ? 0.0 : s->h);
    if (req.method == "dem")
      dem_map(*s, center, count, r);
    else
      heat_map(*s, req, count, r, ctx);
  }
  r.t_spec = req.t.empty() ? format_number(r.t_factor) + "h2" : req.t;
  for (size_t p = 0; p < r.patch.size(); ++p)
    if (!std::isfinite(r.u[p]) || !std::isfinite(r.v[p]))
      fail(ErrorCode::Numerical,
           "the log map is not finite at vertex " + std::to_string(r.patch[p]) +
               (r.heat_underflow_vertices > 0
                    ? "; the heat underflowed at " + std::to_string(r.heat_underflow_vertices) +
                          " patch vertices: t = " + format_number(r.t_avoiding_underflow) + " avoids it"
                    : std::string()));
  if (!r.polygon) injectivity(s->mesh, req.clip_injective, r);
  for (double x : r.distance) r.max_distance = std::max(r.max_distance, x);
  if (r.heat_underflow_vertices > 0)
    r.warnings.push_back(underflow_warning(
        r.heat_underflow_vertices, r.t_avoiding_underflow, r.h,
        " patch vertices (no direction there: distances interpolated, angles unreliable); "));
  return r;
}

}  // namespace locus
