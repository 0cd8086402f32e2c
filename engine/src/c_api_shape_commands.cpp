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

using namespace locus::c_api_detail;

extern "C" {

locus_deform_options locus_deform_options_default(void) {
  const locus::DeformCommandRequest d;
  locus_deform_options o;
  std::memset(&o, 0, sizeof o);
  o.roi_seed = d.roi_seed;
  o.roi_fraction = d.roi_fraction;
  o.handle = d.handle;
  o.handle_ring = d.handle_ring;
  o.regularization = d.regularization;
  return o;  // energy NULL: the request's default
}

locus_status locus_deform_run(locus_session* session, const locus_deform_options* options, double* out_xyz,
                              locus_deform_report* out_report, const locus_run_options* opts) {
  return guarded("locus_deform_run", [&] {
    locus::Session& s = session_of(session);
    require(options != nullptr, "options is NULL");
    require(out_xyz != nullptr, "out_xyz is NULL");
    CallContext cc(opts);
    if (cc.t_factor != 0.0) fail(ErrorCode::BadUsage, "opts->t_factor must be 0 here: deform has no diffusion time");
    locus::DeformCommandRequest q;
    q.roi_seed = options->roi_seed;
    q.roi_fraction = options->roi_fraction;
    q.handle = options->handle;
    q.handle_ring = options->handle_ring;
    q.offset = {options->offset[0], options->offset[1], options->offset[2]};
    if (options->energy && options->energy[0]) q.energy = options->energy;
    q.regularization = options->regularization;
    if (options->save) q.save = options->save;
    if (options->load) q.load = options->load;
    const locus::DeformCommandReport r = s.deform(q, cc.ctx);
    std::copy(r.xyz.begin(), r.xyz.end(), out_xyz);
    if (!out_report) return;
    locus_deform_report& o = *out_report;
    std::memset(&o, 0, sizeof o);
    o.roi_vertices = r.roi_vertices, o.handle_vertices = r.handle_vertices, o.free_vertices = r.free_vertices;
    o.columns_updated_fraction = r.columns_updated_fraction;
    o.refinement_steps = r.refinement_steps;
    o.residual = r.residual, o.max_displacement = r.max_displacement;
    o.global_factor_s = r.order_s + r.analyze_s + r.factor_s;
    o.update_s = r.update_s, o.solve_s = r.solve_s;
  });
}

}  // extern "C"

// The param command (locus.h, locus_param_options).
extern "C" {

locus_param_options locus_param_options_default(void) {
  const locus::ParamRequest d;
  locus_param_options o;
  std::memset(&o, 0, sizeof o);
  o.iters = d.iters;
  o.eps = d.eps;
  o.center = d.center;
  o.fraction = d.fraction;
  return o;  // method, boundary NULL: the request's defaults
}

locus_status locus_param_run(locus_session* session, const locus_param_options* options, double* out_uv,
                             locus_param_report* out_report, const locus_run_options* opts) {
  return guarded("locus_param_run", [&] {
    locus::Session& s = session_of(session);
    require(options != nullptr, "options is NULL");
    require(out_uv != nullptr, "out_uv is NULL");
    CallContext cc(opts);
    if (cc.t_factor != 0.0) fail(ErrorCode::BadUsage, "opts->t_factor must be 0 here: param has no diffusion time");
    locus::ParamRequest q;
    if (options->method && options->method[0]) q.method = options->method;
    q.iters = options->iters;
    q.eps = options->eps;
    q.center = options->center;
    q.fraction = options->fraction;
    if (options->boundary && options->boundary[0]) q.boundary = options->boundary;
    if (options->save) q.save = options->save;
    if (options->load) q.load = options->load;
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
    if (!out_report) return;
    locus_param_report& o = *out_report;
    std::memset(&o, 0, sizeof o);
    o.patch_size = q.center < 0 ? static_cast<int64_t>(n) : static_cast<int64_t>(r.patch_vertices.size());
    o.flipped_faces = r.flipped_faces, o.degenerate_faces = r.degenerate_faces;
    o.negative_weights = r.negative_weights;
    o.boundary_vertices = r.boundary_vertices;
    o.converged = r.converged ? 1 : 0, o.iterations = r.iterations;
    o.query_s = q.center < 0 ? r.param_s : r.query_s;
  });
}

}  // extern "C"

// The perfect-laplacian and selfsupport commands (locus.h, locus_perfect_laplacian_options,
// locus_selfsupport_options).
extern "C" {

locus_perfect_laplacian_options locus_perfect_laplacian_options_default(void) {
  const locus::PerfectLaplacianCommandRequest d;
  locus_perfect_laplacian_options o;
  std::memset(&o, 0, sizeof o);
  o.planar = d.planar ? 1 : 0;
  o.iters = d.iters;
  o.eps = d.eps;
  o.anderson = d.anderson;
  o.no_active_set = d.no_active_set ? 1 : 0;
  o.noise = d.noise;
  o.seed = d.seed;
  return o;  // method NULL: the request's default
}

locus_status locus_perfect_laplacian_run(locus_session* session, const locus_perfect_laplacian_options* options,
                                         int32_t* out_edges, double* out_weights, double* out_xyz,
                                         int32_t* out_converged, const locus_run_options* opts) {
  return guarded("locus_perfect_laplacian_run", [&] {
    locus::Session& s = session_of(session);
    require(options != nullptr, "options is NULL");
    CallContext cc(opts);
    locus::PerfectLaplacianCommandRequest q;
    q.planar = options->planar != 0;
    q.iters = options->iters;
    q.eps = options->eps;
    if (options->method && options->method[0]) q.method = options->method;
    q.anderson = options->anderson;
    q.no_active_set = options->no_active_set != 0;
    q.noise = options->noise;
    q.seed = options->seed;
    const locus::PerfectLaplacianCommandReport r = s.perfect_laplacian(q, cc.ctx);
    copy_edges(r.edges, r.weights, r.xyz, out_edges, out_weights, out_xyz);
    if (out_converged) *out_converged = r.converged ? 1 : 0;
  });
}

locus_selfsupport_options locus_selfsupport_options_default(void) {
  const locus::SelfSupportCommandRequest d;
  locus_selfsupport_options o;
  std::memset(&o, 0, sizeof o);
  o.load_density = d.load_density;
  o.iters = d.iters;
  o.eps = d.eps;
  return o;  // support NULL: the request's default
}

locus_status locus_selfsupport_run(locus_session* session, const locus_selfsupport_options* options,
                                   int32_t* out_edges, double* out_forces, double* out_xyz, int32_t* out_converged,
                                   const locus_run_options* opts) {
  return guarded("locus_selfsupport_run", [&] {
    locus::Session& s = session_of(session);
    require(options != nullptr, "options is NULL");
    CallContext cc(opts);
    locus::SelfSupportCommandRequest q;
    if (options->support && options->support[0]) q.support = options->support;
    q.load_density = options->load_density;
    q.iters = options->iters;
    q.eps = options->eps;
    const locus::SelfSupportCommandReport r = s.self_supporting(q, cc.ctx);
    copy_edges(r.edges, r.forces, r.xyz, out_edges, out_forces, out_xyz);
    if (out_converged) *out_converged = r.converged ? 1 : 0;
  });
}

}  // extern "C"
