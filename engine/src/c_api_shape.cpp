// The C API's shape calls (locus.h): deformation, parameterizations, perfect
// Laplacians and self-supporting surfaces.
#include "c_api_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace locus::c_api_detail;

extern "C" {

locus_status locus_deform(locus_session* session, const locus_deform_request* request, double* out_xyz,
                          const locus_run_options* opts) {
  return session_run("locus_deform", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(request != nullptr, "request is NULL");
    require(out_xyz != nullptr, "out_xyz is NULL");
    locus::DeformRequest r;
    r.roi_seed = vertex_id(s, request->roi_seed, "request->roi_seed");
    r.handle_vertex = vertex_id(s, request->handle_vertex, "request->handle_vertex");
    r.roi_fraction = request->roi_fraction;
    r.handle_ring = request->handle_ring;
    r.offset = {request->offset[0], request->offset[1], request->offset[2]};
    r.energy = request->bilaplacian ? locus::DeformEnergyKind::Bilaplacian : locus::DeformEnergyKind::Laplacian;
    const locus::DeformResult d = s.deform(r, cc.ctx);
    std::copy(d.xyz.begin(), d.xyz.end(), out_xyz);
  });
}

locus_status locus_param_disk(locus_session* session, int32_t method, int32_t max_iterations, double eps,
                              double* out_uv, int64_t* out_flipped, const locus_run_options* opts) {
  return session_run("locus_param_disk", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_uv != nullptr, "out_uv is NULL");
    if (method < 0 || method > 2)
      fail(ErrorCode::BadUsage, "method = " + std::to_string(method) + " is not 0 (perfect), 1 (cotan) or 2 (uniform)");
    locus::DiskParamRequest r;
    r.method = method == 1 ? locus::DiskParamMethod::Cotan
               : method == 2 ? locus::DiskParamMethod::Uniform : locus::DiskParamMethod::Perfect;
    r.max_iterations = max_iterations;
    r.eps = eps;
    const locus::DiskParamResult p = s.parameterize_disk(r, cc.ctx);
    std::copy(p.uv.begin(), p.uv.end(), out_uv);
    if (out_flipped) *out_flipped = p.flipped_faces;
  });
}

locus_status locus_param_patch(locus_session* session, int64_t center, double fraction, int32_t boundary,
                               double* out_uv, int64_t* out_patch_size, int64_t* out_flipped,
                               const locus_run_options* opts) {
  return session_run("locus_param_patch", session, opts, [&](locus::Session& s, CallContext& cc) {
    require(out_uv != nullptr, "out_uv is NULL");
    if (boundary != 0 && boundary != 1)
      fail(ErrorCode::BadUsage, "boundary = " + std::to_string(boundary) + " is not 0 (Neumann) or 1 (circle)");
    locus::PatchParamRequest r;
    r.center = vertex_id(s, center, "center");
    r.fraction = fraction;
    r.boundary = boundary == 1 ? locus::PatchBoundary::Circle : locus::PatchBoundary::Neumann;
    const locus::PatchParamResult p = s.parameterize_patch(r, cc.ctx);
    const size_t n = static_cast<size_t>(s.num_vertices());
    std::fill(out_uv, out_uv + 2 * n, std::numeric_limits<double>::quiet_NaN());
    for (size_t k = 0; k < p.vertices.size(); ++k) {
      out_uv[2 * static_cast<size_t>(p.vertices[k])] = p.uv[2 * k];
      out_uv[2 * static_cast<size_t>(p.vertices[k]) + 1] = p.uv[2 * k + 1];
    }
    if (out_patch_size) *out_patch_size = static_cast<int64_t>(p.vertices.size());
    if (out_flipped) *out_flipped = p.flipped_faces;
  });
}

int64_t locus_session_edge_count(const locus_session* session) {
  return count_of("locus_session_edge_count", session, "session is NULL",
                  [&] { return session->session.num_edges(); });
}

locus_status locus_perfect_laplacian(locus_session* session, int32_t planar, int32_t max_iterations, double eps,
                                     int32_t* out_edges, double* out_weights, double* out_xyz,
                                     int32_t* out_converged, const locus_run_options* opts) {
  return session_run("locus_perfect_laplacian", session, opts, [&](locus::Session& s, CallContext& cc) {
    const locus::PerfectLaplacianRequest r{.planar = planar != 0, .max_iterations = max_iterations, .eps = eps};
    const locus::PerfectLaplacianOutput p = s.perfect_laplacian(r, cc.ctx);
    copy_edges(p.edges, p.weights, p.xyz, out_edges, out_weights, out_xyz);
    if (out_converged) *out_converged = p.converged ? 1 : 0;
  });
}

locus_status locus_self_supporting(locus_session* session, double load_density, int32_t max_iterations, double eps,
                                   int32_t* out_edges, double* out_forces, double* out_xyz, int32_t* out_converged,
                                   const locus_run_options* opts) {
  return session_run("locus_self_supporting", session, opts, [&](locus::Session& s, CallContext& cc) {
    const locus::SelfSupportRequest r{.load_density = load_density, .max_iterations = max_iterations, .eps = eps};
    const locus::SelfSupportOutput p = s.self_supporting(r, cc.ctx);
    copy_edges(p.edges, p.forces, p.xyz, out_edges, out_forces, out_xyz);
    if (out_converged) *out_converged = p.converged ? 1 : 0;
  });
}

}  // extern "C"
