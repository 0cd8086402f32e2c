// `geodesic` as every front end runs it (engine/include/locus/engine/
// geodesic_requests.hpp): heat geodesic distance from one vertex (thesis
// §6.4.1, Crane et al. 2013) on the whole mesh with full solves, or localized
// to the geodesic disk of round(fraction * n) vertices around the source with
// exact subset solves (§6.4.2); on a polygon mesh, the whole-mesh heat method
// on the polygon operators (pipelines/.../geodesic/polygon_heat_geodesic.hpp).
//
// No value (outside the patch, or in another component than the source) is
// NaN with `valid` 0, as in every output format (README "Output formats"); a
// NaN from the solver is never an answer (Error(Numerical)).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "locus/engine/factor_store.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {

using namespace session_detail;

void check_request(const GeodesicRequest& req) {
  check_fraction(req.fraction);
  heat_method_time(req.t, req.t_factor);
  check_factor_cache_files({req.save, req.load});
}

namespace session_detail {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void check_fraction(double fraction) {
  if (!(fraction > 0 && fraction <= 1))
    fail(ErrorCode::BadUsage, "fraction must be in (0, 1] (got " + format_number(fraction) + ")");
}

HeatTime heat_method_time(const std::string& t, const std::optional<double>& t_factor) {
  return heat_time_of(t, t_factor, HeatTime{HeatGeodesicOptions{}.t_factor, true});
}

std::shared_ptr<const HeatLogMap> heat_method_engine(State& s, double t_factor, const FactorCacheFiles& files,
                                                     FactorCacheReport& report, const RunContext& ctx) {
  if (!files.used()) return engine(s, HeatQuery{t_factor}, ctx);
  // With a factor cache the engine is the caller's own (not cached: the
  // file decides its factors): the heat operator labelled with t, the
  // Poisson operator with poisson_rel, on one symbolic factor.
  LogMapOptions mo;
  mo.geodesic.t_factor = t_factor;
  CscMatrix A, P;
  const double t = HeatGeodesic::operators(s.mesh, mo.geodesic, A, P);
  const FactorRequest req[2] = {{"heat", t, &A}, {"poisson", mo.geodesic.poisson_rel, &P}};
  Factors F = factor_or_load(files, s.mesh, req, ctx);
  report.loaded = files.load;
  report.saved = files.save;
  report.load_s = F.load_s;
  report.save_s = F.save_s;
  return std::make_shared<const HeatLogMap>(s.mesh, mo,
                                            HeatGeodesicFactors{std::move(F.factors[0]), std::move(F.factors[1])});
}

std::string underflow_warning(int64_t vertices, double t_no_underflow, double h, const char* what) {
  return "the heat underflowed at " + std::to_string(vertices) + what + "--t " +
         format_number(t_no_underflow / (h * h)) + "h2 (t = " + format_number(t_no_underflow) + ") avoids it";
}

namespace {

GeodesicReport polygon_geodesic_report(State& s, const GeodesicRequest& req, const HeatTime& time,
                                       const RunContext& ctx) {
  GeodesicReport r;
  const bool given = !req.t.empty() || req.t_factor.has_value();
  const double tf = given ? heat_time_factor(time, time.times_h2 ? 0.0 : mean_edge_length(*s.polygons)) : 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  const auto e = polygon_engine(s, HeatQuery{tf}, ctx);  // polygon_geodesic below finds it built
  r.precompute_s = seconds_since(t0);
  const int32_t n = s.mesh.num_vertices();
  r.distance.assign(static_cast<size_t>(n), 0.0);
  const auto t1 = std::chrono::steady_clock::now();
  polygon_geodesic(s, static_cast<int32_t>(req.source), View<double>(r.distance), HeatQuery{tf}, ctx);
  r.query_s = seconds_since(t1);
  r.method = "heat-full-polygon";
  r.t_factor = polygon_t_factor(HeatQuery{tf});
  r.t = e->geodesic().time();
  r.h = e->geodesic().mean_edge_length();
  r.patch_size = n;
  return r;
}

// The distances from req.source on `geo`: the whole mesh, or the geodesic
// disk of round(fraction * n) vertices with exact subset solves.
void query_distances(State& s, const HeatGeodesic& geo, const GeodesicRequest& req, GeodesicReport& r,
                     const RunContext& ctx) {
  const int32_t n = s.mesh.num_vertices();
  const int32_t source = static_cast<int32_t>(req.source);
  const bool local = req.fraction < 1.0;
  r.distance.assign(static_cast<size_t>(n), std::numeric_limits<double>::quiet_NaN());
  r.valid.assign(static_cast<size_t>(n), local ? 0.0 : 1.0);
  HeatGeodesicWorkspace ws;
  r.patch_size = n;
  if (local) {
    const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(req.fraction * n)));
    const auto g = grower(s, ctx);
    PatchWorkspace pws;
    std::vector<int32_t> patch;
    auto t0 = std::chrono::steady_clock::now();
    grow_patch_vertices(*g, source, geodesic_disk(count), pws, patch);
    r.patch_s = seconds_since(t0);
    r.patch_size = static_cast<int32_t>(patch.size());
    std::vector<double> d(patch.size());
    t0 = std::chrono::steady_clock::now();
    geo.query(source, patch, d, ws);
    r.query_s = seconds_since(t0);
    for (size_t k = 0; k < patch.size(); ++k) {
      r.distance[patch[k]] = d[k];
      r.valid[patch[k]] = 1;
    }
  } else {
    const auto t0 = std::chrono::steady_clock::now();
    geo.query_full(source, r.distance, ws);
    r.query_s = seconds_since(t0);
  }
  r.method = local ? "heat-local" : "heat-full";
  r.t = geo.time();
  r.h = geo.mean_edge_length();
  r.heat_underflow_vertices = ws.underflow;
  if (ws.underflow > 0) {
    r.t_avoiding_underflow = ws.t_no_underflow;
    r.warnings.push_back(underflow_warning(ws.underflow, ws.t_no_underflow, r.h,
                                           " vertices (no direction there: their distances are interpolated); "));
  }
  if (ws.dips > 0)
    r.warnings.push_back("the distance dipped below zero at " + std::to_string(ws.dips) +
                         (ws.dips == 1 ? " vertex" : " vertices") + ", by at most " +
                         format_number(ws.deepest_dip) + " (" + format_number(ws.deepest_dip / r.h) +
                         " h): set to 0 (the heat method's discretization error)");
}

// may_fall_back: the operator is `auto` on a clean mesh (cotan). Where the
// cotan heat method's distance comes out negative (obtuse, badly shaped
// triangles: the thesis' §6.4 caveat), the query is answered on the robust
// operator, whose intrinsic Delaunay triangles have no such trouble, and the
// report says so; with `cotan` asked, the error stands.
GeodesicReport triangle_geodesic_report(State& s, const GeodesicRequest& req, const HeatTime& time,
                                        bool may_fall_back, const RunContext& ctx) {
  GeodesicReport r;
  r.t_factor = heat_time_factor(time, time.times_h2 ? 0.0 : s.h);
  const bool cache = req.save.size() + req.load.size() > 0;
  if (cache && s.robust)
    fail(ErrorCode::BadUsage, "--save/--load: the factor cache holds the cotan operator's factors; " +
                                  mesh_name(s.mesh) + " runs on the robust operator");
  const CallProgress progress(ctx, cache || !geodesic_engine_cached(s, HeatQuery{r.t_factor}));
  auto t0 = std::chrono::steady_clock::now();
  try {
    std::shared_ptr<const HeatGeodesic> e;
    if (s.robust) {
      e = geodesic_engine(s, HeatQuery{r.t_factor}, progress.build());
    } else {
      const auto lm = heat_method_engine(s, r.t_factor, {req.save, req.load}, r.factor_cache, progress.build());
      e = std::shared_ptr<const HeatGeodesic>(lm, &lm->geodesic());
    }
    r.precompute_s = seconds_since(t0);
    ctx.check_cancel();
    query_distances(s, *e, req, r, ctx);
  } catch (const Error& err) {  // a factorization that is not positive definite, or negative distances
    if (!may_fall_back || err.code() != ErrorCode::Numerical) throw;
    r.operator_fallback = std::string("the cotan heat method failed (") + err.what() +
                          "); answered on the robust operator";
    r.warnings.clear();
    t0 = std::chrono::steady_clock::now();
    try {
      const auto e = robust_geodesic_engine(s, HeatQuery{r.t_factor}, ctx);
      r.precompute_s = seconds_since(t0);
      query_distances(s, *e, req, r, ctx);
    } catch (const Error& again) {
      if (again.code() != ErrorCode::Numerical) throw;
      fail(ErrorCode::Numerical, std::string(again.what()) + " (robust operator; the cotan operator had failed first: " +
                                     err.what() + ")", again.where());
    }
    r.warnings.push_back(r.operator_fallback);
  }
  progress.finish("geodesic distance");
  return r;
}

}  // namespace
}  // namespace session_detail

bool keeps_polygons(const GeodesicRequest& req) {
  return !(req.fraction < 1.0) && req.save.empty() && req.load.empty();
}

GeodesicReport Session::geodesic(const GeodesicRequest& req, const RunContext& ctx) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  check_vertex(*s, req.source, "source");
  const HeatTime time = heat_method_time(req.t, req.t_factor);
  const bool may_fall_back = impl_->robust_fallback && !s->robust;
  GeodesicReport r;
  if (s->polygons && !s->robust && keeps_polygons(req)) {
    try {
      r = polygon_geodesic_report(*s, req, time, ctx);
    } catch (const Error& err) {
      // With auto, a polygon whose operators cannot be built (a virtual
      // triangle of no area) is answered on the mesh's triangulation instead.
      if (!impl_->robust_fallback || (err.code() != ErrorCode::BadInput && err.code() != ErrorCode::Numerical)) throw;
      r = triangle_geodesic_report(*s, req, time, may_fall_back, ctx);
      const std::string why = std::string("the polygon operators failed (") + err.what() +
                              "); answered on the triangulation";
      r.warnings.insert(r.warnings.begin(), why);
      r.operator_fallback = why + (r.operator_fallback.empty() ? "" : "; " + r.operator_fallback);
    }
  } else {
    r = triangle_geodesic_report(*s, req, time, may_fall_back, ctx);
  }
  r.source = static_cast<int32_t>(req.source);
  r.fraction = req.fraction;
  r.t_spec = req.t.empty() ? format_number(r.t_factor) + "h2" : req.t;
  // +infinity = another connected component than the source (no path): no
  // value, counted. A NaN from the solver never is an answer.
  r.valid.resize(r.distance.size(), 1.0);
  for (size_t i = 0; i < r.distance.size(); ++i) {
    double& d = r.distance[i];
    if (r.valid[i] == 0) continue;
    if (std::isinf(d) || (std::isnan(d) && r.method == "heat-full-polygon")) {  // polygon: NaN = other component
      d = std::numeric_limits<double>::quiet_NaN();
      r.valid[i] = 0;
      ++r.unreachable;
      continue;
    }
    if (!std::isfinite(d))
      fail(ErrorCode::Numerical, "the heat geodesic distance is not finite (t = " + format_number(r.t) + ")");
    r.max_distance = std::max(r.max_distance, d);
  }
  return r;
}

}  // namespace locus
