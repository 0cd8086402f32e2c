// The C API's heat-method calls (locus.h): geodesic distance from one vertex
// or a set of points, log maps, the valid mask.
#include "c_api_support.hpp"
#include "field_copy.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

using namespace locus::c_api_detail;

// What the geodesic and logmap reports share: the time, the farthest distance,
// the underflow diagnosis and the timings.
#define LOCUS_HEAT_REPORT_FIELDS \
  t_factor, t, h, max_distance, heat_underflow_vertices, t_avoiding_underflow, precompute_s, patch_s, query_s

namespace {

// The time of a C request: its own t / t_factor, or the run options' t_factor
// (the older calls' spelling) when it gives none; not both.
void set_time(std::string& t, std::optional<double>& t_factor, const char* t_text, double factor,
              const CallContext& cc) {
  t = text(t_text);
  if (factor != 0.0) t_factor = factor;
  if (cc.t_factor != 0.0) {
    if (t_factor || !t.empty())
      fail(ErrorCode::BadUsage, "the time is given twice: in the options (t or t_factor) and in opts->t_factor");
    t_factor = cc.t_factor;
  }
}

locus::GeodesicRequest request_of(const locus_geodesic_options& o, const CallContext& cc) {
  locus::GeodesicRequest q;
  LOCUS_COPY_FIELDS(q, o, source, fraction, save, load);
  set_time(q.t, q.t_factor, o.t, o.t_factor, cc);
  return q;
}

locus::LogmapRequest request_of(const locus_logmap_options& o, const CallContext& cc) {
  locus::LogmapRequest q;
  LOCUS_COPY_FIELDS(q, o, center, fraction, method, angle, lattice, recenter, clip_injective, save, load);
  set_time(q.t, q.t_factor, o.t, o.t_factor, cc);
  return q;
}

locus_geodesic_report report_of(const locus::GeodesicReport& r) {
  locus_geodesic_report o;
  std::memset(&o, 0, sizeof o);
  LOCUS_COPY_FIELDS(o, r, patch_size, unreachable, LOCUS_HEAT_REPORT_FIELDS);
  return o;
}

locus_logmap_report report_of(const locus::LogmapReport& r) {
  locus_logmap_report o;
  std::memset(&o, 0, sizeof o);
  o.patch_size = static_cast<int64_t>(r.patch.size());
  LOCUS_COPY_FIELDS(o, r, flipped, injectivity_radius, clipped_vertices, sources, batches, passes, angle_fallbacks,
                    two_ring, recentered, LOCUS_HEAT_REPORT_FIELDS);
  return o;
}

}  // namespace

extern "C" {

locus_geodesic_options locus_geodesic_options_default(void) {
  return LOCUS_C_DEFAULTS(locus_geodesic_options, locus::GeodesicRequest, source, fraction);
}

locus_logmap_options locus_logmap_options_default(void) {
  // method, angle, lattice, recenter NULL: the request's defaults
  return LOCUS_C_DEFAULTS(locus_logmap_options, locus::LogmapRequest, center, fraction, clip_injective);
}

locus_status locus_geodesic_run(locus_session* session, const locus_geodesic_options* options, double* out_nv,
                                locus_geodesic_report* out_report, const locus_run_options* opts) {
  return timed_command_run("locus_geodesic_run", session, options, {out_nv, "out_nv is NULL"}, opts,
                           [&](locus::Session& s, CallContext& cc) {
    const locus::GeodesicReport r = s.geodesic(request_of(*options, cc), cc.ctx);
    std::copy(r.distance.begin(), r.distance.end(), out_nv);
    if (out_report) *out_report = report_of(r);
  });
}

locus_status locus_geodesic_distance_ex(locus_session* session, int64_t source, double* out_nv,
                                        const locus_run_options* opts) {
  // Straight into the caller's buffer (no report arrays): every block of a
  // query goes through the host's allocator (tests/interpose).
  return session_run("locus_geodesic_distance", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_nv != nullptr, "out_nv is NULL");
    const int32_t src = vertex_id(s, source, "source");
    s.geodesic_distance(src, std::span<double>(out_nv, static_cast<size_t>(s.num_vertices())), cc.heat(), cc.ctx);
    no_value_as_nan(out_nv, s.num_vertices());
  });
}

locus_status locus_geodesic_distance(locus_session* session, int64_t source, double* out_nv) {
  return locus_geodesic_distance_ex(session, source, out_nv, nullptr);
}

locus_status locus_logmap_run(locus_session* session, const locus_logmap_options* options, double* out_uv,
                              double* out_distance, double* out_angle, locus_logmap_report* out_report,
                              const locus_run_options* opts) {
  return timed_command_run("locus_logmap_run", session, options, {out_uv, "out_uv is NULL"}, opts,
                           [&](locus::Session& s, CallContext& cc) {
    const locus::LogmapReport r = s.logmap(request_of(*options, cc), cc.ctx);
    const size_t n = static_cast<size_t>(s.num_vertices());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::fill(out_uv, out_uv + 2 * n, nan);
    if (out_distance) std::fill(out_distance, out_distance + n, nan);
    if (out_angle) std::fill(out_angle, out_angle + n, nan);
    for (size_t k = 0; k < r.patch.size(); ++k) {
      const size_t i = static_cast<size_t>(r.patch[k]);
      out_uv[2 * i] = r.u[k];
      out_uv[2 * i + 1] = r.v[k];
      if (out_distance) out_distance[i] = r.distance[k];
      if (out_angle) out_angle[i] = r.angle[k];
    }
    if (out_report) *out_report = report_of(r);
  });
}

locus_status locus_logmap_ex(locus_session* session, int64_t center, double fraction, double* out_uv,
                             const locus_run_options* opts) {
  // The Session's log map keeps its arrays in the host's allocator (LogMapResult).
  return session_run("locus_logmap", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_uv != nullptr, "out_uv is NULL");
    const int32_t c = vertex_id(s, center, "center");
    const locus::LogMapResult r = s.logmap(c, fraction, cc.heat(), cc.ctx);
    const size_t n = static_cast<size_t>(s.num_vertices());
    std::fill(out_uv, out_uv + 2 * n, std::numeric_limits<double>::quiet_NaN());
    for (size_t k = 0; k < r.patch.size(); ++k) {
      out_uv[2 * static_cast<size_t>(r.patch[k])] = r.u[k];
      out_uv[2 * static_cast<size_t>(r.patch[k]) + 1] = r.v[k];
    }
  });
}

int64_t locus_valid_mask(const double* values, int64_t count, int64_t stride, int32_t* out_valid) {
  clear_error();
  if (!values || !out_valid || count < 0 || stride < 1) {
    set_error("locus_valid_mask", !values      ? "values is NULL"
                                  : !out_valid ? "out_valid is NULL"
                                  : count < 0  ? "count < 0"
                                               : "stride < 1");
    return -1;
  }
  int64_t valid = 0;
  for (int64_t i = 0; i < count; ++i) {
    out_valid[i] = std::isnan(values[i * stride]) ? 0 : 1;
    valid += out_valid[i];
  }
  return valid;
}

locus_status locus_logmap(locus_session* session, int64_t center, double fraction, double* out_uv) {
  return locus_logmap_ex(session, center, fraction, out_uv, nullptr);
}

locus_status locus_geodesic_distance_multi(locus_session* session, const locus_surface_point* sources,
                                           int64_t n_sources, double* out_nv, const locus_run_options* opts) {
  return session_run("locus_geodesic_distance_multi", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_nv != nullptr, "out_nv is NULL");
    const std::vector<locus::MeshPoint> pts = mesh_points(s, sources, n_sources, "sources");
    s.geodesic_distance(pts, std::span<double>(out_nv, static_cast<size_t>(s.num_vertices())), cc.heat(), cc.ctx);
    no_value_as_nan(out_nv, s.num_vertices());
  });
}

}  // extern "C"
