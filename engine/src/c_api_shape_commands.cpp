// The C API of the shape commands: deform, param, perfect-laplacian and
// selfsupport (locus.h, locus_*_options): the C options translated to the
// engine's requests (engine/include/locus/engine/deform_request.hpp,
// param_request.hpp, laplacian_requests.hpp), run by the Session, the report
// copied out. Every check beyond C's own is the Session's.
#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include "c_api_support.hpp"
#include "field_copy.hpp"

using namespace locus::c_api_detail;

// The numeric options of each command (its strings are NULL in the C defaults).
#define LOCUS_DEFORM_NUMBERS roi_seed, roi_fraction, handle, handle_ring, regularization
#define LOCUS_PARAM_NUMBERS iters, eps, center, fraction
#define LOCUS_PERFECT_LAPLACIAN_NUMBERS planar, iters, eps, anderson, no_active_set, noise, seed
#define LOCUS_SELFSUPPORT_NUMBERS load_density, iters, eps

namespace {

locus::DeformCommandRequest request_of(const locus_deform_options& o) {
  locus::DeformCommandRequest q;
  LOCUS_COPY_FIELDS(q, o, LOCUS_DEFORM_NUMBERS, energy, save, load);
  q.offset = {o.offset[0], o.offset[1], o.offset[2]};
  return q;
}

}  // namespace

extern "C" {

locus_deform_options locus_deform_options_default(void) {
  // energy NULL: the request's default
  return LOCUS_C_DEFAULTS(locus_deform_options, locus::DeformCommandRequest, LOCUS_DEFORM_NUMBERS);
}

locus_status locus_deform_run(locus_session* session, const locus_deform_options* options, double* out_xyz,
                              locus_deform_report* out_report, const locus_run_options* opts) {
  return command_run("locus_deform_run", session, options, {out_xyz, "out_xyz is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    const locus::DeformCommandReport r = s.deform(request_of(*options), cc.ctx);
    std::copy(r.xyz.begin(), r.xyz.end(), out_xyz);
    report_into(out_report, [&](locus_deform_report& o) {
      LOCUS_COPY_FIELDS(o, r, roi_vertices, handle_vertices, free_vertices, columns_updated_fraction,
                        refinement_steps, residual, max_displacement, update_s, solve_s);
      o.global_factor_s = r.order_s + r.analyze_s + r.factor_s;
    });
  });
}

}  // extern "C"

// The param command (locus.h, locus_param_options).
extern "C" {

locus_param_options locus_param_options_default(void) {
  // method, boundary NULL: the request's defaults
  return LOCUS_C_DEFAULTS(locus_param_options, locus::ParamRequest, LOCUS_PARAM_NUMBERS);
}

locus_status locus_param_run(locus_session* session, const locus_param_options* options, double* out_uv,
                             locus_param_report* out_report, const locus_run_options* opts) {
  return command_run("locus_param_run", session, options, {out_uv, "out_uv is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    locus::ParamRequest q;
    LOCUS_COPY_FIELDS(q, *options, LOCUS_PARAM_NUMBERS, method, boundary, save, load);
    const locus::ParamReport r = s.param(q, cc.ctx);
    const size_t n = static_cast<size_t>(s.num_vertices());
    if (q.center < 0) {
      std::copy(r.uv.begin(), r.uv.end(), out_uv);
    } else {
      std::fill(out_uv, out_uv + 2 * n, std::numeric_limits<double>::quiet_NaN());
      for (size_t k = 0; k < r.patch_vertices.size(); ++k) {
        out_uv[2 * static_cast<size_t>(r.patch_vertices[k])] = r.uv[2 * k];
        out_uv[2 * static_cast<size_t>(r.patch_vertices[k]) + 1] = r.uv[2 * k + 1];
      }
    }
    report_into(out_report, [&](locus_param_report& o) {
      o.patch_size = q.center < 0 ? static_cast<int64_t>(n) : static_cast<int64_t>(r.patch_vertices.size());
      LOCUS_COPY_FIELDS(o, r, flipped_faces, degenerate_faces, negative_weights, boundary_vertices, converged,
                        iterations);
      o.query_s = q.center < 0 ? r.param_s : r.query_s;
    });
  });
}

}  // extern "C"

// The perfect-laplacian and selfsupport commands (locus.h, locus_perfect_laplacian_options,
// locus_selfsupport_options).
extern "C" {

locus_perfect_laplacian_options locus_perfect_laplacian_options_default(void) {
  // method NULL: the request's default
  return LOCUS_C_DEFAULTS(locus_perfect_laplacian_options, locus::PerfectLaplacianCommandRequest,
                          LOCUS_PERFECT_LAPLACIAN_NUMBERS);
}

locus_status locus_perfect_laplacian_run(locus_session* session, const locus_perfect_laplacian_options* options,
                                         int32_t* out_edges, double* out_weights, double* out_xyz,
                                         int32_t* out_converged, const locus_run_options* opts) {
  return command_run("locus_perfect_laplacian_run", session, options, {}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    locus::PerfectLaplacianCommandRequest q;
    LOCUS_COPY_FIELDS(q, *options, LOCUS_PERFECT_LAPLACIAN_NUMBERS, method);
    const locus::PerfectLaplacianCommandReport r = s.perfect_laplacian(q, cc.ctx);
    copy_edges(r.edges, r.weights, r.xyz, out_edges, out_weights, out_xyz);
    if (out_converged) *out_converged = r.converged ? 1 : 0;
  });
}

locus_selfsupport_options locus_selfsupport_options_default(void) {
  // support NULL: the request's default
  return LOCUS_C_DEFAULTS(locus_selfsupport_options, locus::SelfSupportCommandRequest, LOCUS_SELFSUPPORT_NUMBERS);
}

locus_status locus_selfsupport_run(locus_session* session, const locus_selfsupport_options* options,
                                   int32_t* out_edges, double* out_forces, double* out_xyz, int32_t* out_converged,
                                   const locus_run_options* opts) {
  return command_run("locus_selfsupport_run", session, options, {}, opts, [&](locus::Session& s, CallContext& cc) {
    locus::SelfSupportCommandRequest q;
    LOCUS_COPY_FIELDS(q, *options, LOCUS_SELFSUPPORT_NUMBERS, support);
    const locus::SelfSupportCommandReport r = s.self_supporting(q, cc.ctx);
    copy_edges(r.edges, r.forces, r.xyz, out_edges, out_forces, out_xyz);
    if (out_converged) *out_converged = r.converged ? 1 : 0;
  });
}

}  // extern "C"
