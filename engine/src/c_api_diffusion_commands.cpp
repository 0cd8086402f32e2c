// The C API of the adf, hks, heat and nncoords commands (locus.h, "The adf,
// hks and heat commands", locus_nncoords_options): the C options translated to the engine's requests
// (engine/include/locus/engine/diffusion_requests.hpp), run by the Session,
// the report copied out. Every check beyond C's own (NULL arrays, counts) is
// the Session's.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "c_api_support.hpp"
#include "field_copy.hpp"

using namespace locus::c_api_detail;

// The timings of the operator and its factorization, as the reports name them.
#define LOCUS_FACTOR_TIMES operator_s, order_s, analyze_s, numeric_s

namespace {

// The options adf and hks share: the vertices (or all), the method, the factor cache files.
template <class Request, class Options>
void set_signature_options(Request& q, const Options& o) {
  q.vertices = ids(o.vertices, o.n_vertices, "vertices");
  LOCUS_COPY_FIELDS(q, o, all, method, save, load);
}

locus::AdfRequest request_of(const locus_adf_options& o) {
  locus::AdfRequest q;
  LOCUS_COPY_FIELDS(q, o, t);
  set_signature_options(q, o);
  return q;
}

locus::HksRequest request_of(const locus_hks_options& o) {
  locus::HksRequest q;
  if (o.n_ts < 0 || o.n_ts > 4096) fail(ErrorCode::BadUsage, "n_ts must be in 0..4096 (got " + std::to_string(o.n_ts) + ")");
  if (o.n_ts > 0) require(o.ts != nullptr, "ts is NULL");
  for (int64_t k = 0; k < o.n_ts; ++k) {
    require(o.ts[k] != nullptr, ("ts[" + std::to_string(k) + "] is NULL").c_str());
    q.ts.emplace_back(o.ts[k]);
  }
  set_signature_options(q, o);
  return q;
}

void copy_signature(const locus::HeatSignatureReport& r, double* out, double* out_t, locus_signature_report* rep) {
  std::copy(r.values.begin(), r.values.end(), out);
  if (out_t) std::copy(r.t.begin(), r.t.end(), out_t);
  if (!rep) return;
  std::memset(rep, 0, sizeof *rep);
  rep->evaluated = static_cast<int64_t>(r.count());
  LOCUS_COPY_FIELDS(*rep, r, h, nnz_L, supernodes, etree_height, LOCUS_FACTOR_TIMES, query_s);
}

locus::HeatRequest request_of(const locus_heat_options& o) {
  locus::HeatRequest q;
  q.source = ids(o.source, o.n_source, "source");
  q.target = ids(o.target, o.n_target, "target");
  LOCUS_COPY_FIELDS(q, o, t, method, repeat, save, load);
  return q;
}

locus::NncoordsRequest request_of(const locus_nncoords_options& o) {
  locus::NncoordsRequest q;
  q.sites = ids(o.sites, o.n_sites, "sites");
  q.point.face = o.point.face;
  for (int k = 0; k < 3; ++k) q.point.bary[k] = o.point.bary[k];
  LOCUS_COPY_FIELDS(q, o, t);
  return q;
}

}  // namespace

extern "C" {

locus_adf_options locus_adf_options_default(void) {
  // t, method NULL: the request's defaults
  return LOCUS_C_DEFAULTS(locus_adf_options, locus::AdfRequest, all);
}

locus_hks_options locus_hks_options_default(void) {
  return LOCUS_C_DEFAULTS(locus_hks_options, locus::HksRequest, all);
}

locus_heat_options locus_heat_options_default(void) {
  return LOCUS_C_DEFAULTS(locus_heat_options, locus::HeatRequest, repeat);
}

locus_status locus_adf_run(locus_session* session, const locus_adf_options* options, double* out, double* out_t,
                           locus_signature_report* out_report, const locus_run_options* opts) {
  return command_run("locus_adf_run", session, options, {out, "out is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    copy_signature(s.adf(request_of(*options), cc.ctx), out, out_t, out_report);
  });
}

locus_status locus_hks_run(locus_session* session, const locus_hks_options* options, double* out, double* out_t,
                           locus_signature_report* out_report, const locus_run_options* opts) {
  return command_run("locus_hks_run", session, options, {out, "out is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    copy_signature(s.hks(request_of(*options), cc.ctx), out, out_t, out_report);
  });
}

locus_status locus_heat_run(locus_session* session, const locus_heat_options* options, double* out_targets,
                            locus_heat_report* out_report, const locus_run_options* opts) {
  return command_run("locus_heat_run", session, options, {out_targets, "out_targets is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    const locus::HeatReport r = s.heat(request_of(*options), cc.ctx);
    std::copy(r.values.begin(), r.values.end(), out_targets);
    report_into(out_report, [&](locus_heat_report& o) {
      LOCUS_COPY_FIELDS(o, r, t, h, total, nnz_L, etree_height, forward_columns, backward_columns,
                        LOCUS_FACTOR_TIMES, query_s, plan_s, solve_s);
    });
  });
}

}  // extern "C"

extern "C" {

locus_nncoords_options locus_nncoords_options_default(void) {
  const locus::NncoordsRequest d;
  locus_nncoords_options o;
  std::memset(&o, 0, sizeof o);
  o.point.face = d.point.face;
  o.point.vertex = -1;
  for (int k = 0; k < 3; ++k) o.point.bary[k] = d.point.bary[k];
  return o;  // t NULL: the request's "h2"
}

locus_status locus_nncoords_run(locus_session* session, const locus_nncoords_options* options, double* out_weights,
                                locus_nncoords_report* out_report, const locus_run_options* opts) {
  return command_run("locus_nncoords_run", session, options, {out_weights, "out_weights is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    const locus::NncoordsReport r = s.nncoords(request_of(*options), cc.ctx);
    std::copy(r.weights.begin(), r.weights.end(), out_weights);
    report_into(out_report, [&](locus_nncoords_report& o) {
      LOCUS_COPY_FIELDS(o, r, cell_area, clamped, t, at_site, degenerate, fallback_faces, prepare_s, query_s);
    });
  });
}

}  // extern "C"
