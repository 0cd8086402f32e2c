// Session queries of the parameterizations: the flip-free
// parameterization of a disk-like mesh (thesis §2.6, `locus param`) and the
// harmonic parameterization of a patch from the global factor (§4.4, `locus
// param --center`), with Neumann data (eq. 4.6) or the boundary fixed on a
// circle (the factor-once update, chapter 5).
//
// The patch modes reuse the Session's factor of -L_C + eps M (session_heat.cpp,
// laplacian()) and its patch grower: after the first patch query a patch costs
// its own solve (Neumann) or its factor update and solve (Circle). The circle
// mode's updater is built per query (O(structure of L)), so concurrent queries
// share nothing mutable. The disk parameterization refactors per iteration of
// Algorithm 1 and has nothing to cache.
#include <cmath>
#include <string>

#include "field_copy.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/pipelines/laplacian/flipfree_param.hpp"
#include "locus/pipelines/param/patch_param.hpp"
#include "locus/pipelines/param/patch_param_circle.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {

using namespace session_detail;

namespace {

void check_finite_uv(const std::vector<double>& uv, const char* who) {
  for (size_t k = 0; k < uv.size(); ++k)
    if (!std::isfinite(uv[k]))
      fail(ErrorCode::Numerical, std::string(who) + ": the parameterization is not finite at vertex " +
                                     std::to_string(k / 2));
}

void copy_patch(const MeshPatch& p, PatchParamResult& r) {
  r.vertices = p.vertices;
  r.triangles.assign(p.mesh.face_vertices.begin(), p.mesh.face_vertices.end());  // a triangle mesh: 3 local indices per face
}

}  // namespace

DiskParamResult Session::parameterize_disk(const DiskParamRequest& req, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  return parameterize_disk_of(s->polygons ? *s->polygons : s->mesh, req, ctx);  // a polygon mesh as given (session.hpp)
}

DiskParamResult parameterize_disk_of(const Mesh& mesh, const DiskParamRequest& req, const RunContext& ctx) {
  if (req.max_iterations < 1) fail(ErrorCode::BadUsage, "parameterize_disk: max_iterations must be >= 1");
  if (!(req.eps > 0) || !std::isfinite(req.eps))
    fail(ErrorCode::BadUsage, "parameterize_disk: eps must be a finite positive number");
  FlipFreeParamOptions o;
  o.method = req.method == DiskParamMethod::Cotan     ? ParamMethod::Cotan
             : req.method == DiskParamMethod::Uniform ? ParamMethod::Uniform
                                                      : ParamMethod::Perfect;
  o.iteration.max_iterations = req.max_iterations;
  o.iteration.eps = req.eps;
  const CallProgress progress(ctx, false);
  const FlipFreeParamResult f = flipfree_param(mesh, o, progress.query());
  check_finite_uv(f.uv, "parameterize_disk");
  DiskParamResult r;
  r.uv = f.uv;
  r.flipped_faces = f.faces.flipped_faces;
  r.degenerate_faces = f.faces.degenerate_faces;
  LOCUS_COPY_FIELDS(r, f, negative_weights, converged, iterations);
  progress.finish("disk parameterization");
  return r;
}

PatchParamResult Session::parameterize_patch(const PatchParamRequest& req, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  check_vertex(*s, req.center, "parameterize_patch: center");
  if (!(req.fraction > 0 && req.fraction <= 1))
    fail(ErrorCode::BadUsage, "parameterize_patch: fraction must be in (0, 1] (got " + std::to_string(req.fraction) + ")");
  const int32_t count = patch_vertex_count(impl_->nv, req.fraction);
  const CallProgress progress(ctx, !s->laplacian.contains(0));
  const auto L = laplacian(*s, progress.build());
  const auto g = grower(*s, ctx);
  ctx.check_cancel();
  PatchParamResult r;
  if (req.boundary == PatchBoundary::Circle) {
    CirclePatchParameterizer cp(L->factor, L->K, *g);
    const CirclePatchParam P = cp.parameterize(req.center, count, progress.query());
    check_finite_uv(P.uv, "parameterize_patch");
    copy_patch(P.disk.patch, r);
    r.uv = P.uv;
    r.boundary_vertices = static_cast<int32_t>(P.disk.boundary.size());
    r.flipped_faces = P.flips.flipped;
    r.degenerate_faces = P.flips.degenerate;
    r.holes_filled = P.disk.holes_filled;
    progress.finish("patch parameterization");
    return r;
  }
  PatchWorkspace pws;
  SolveWorkspace ws;
  const PatchParam P = locus::parameterize_patch(L->factor, *g, req.center, count, pws, ws);
  check_finite_uv(P.uv, "parameterize_patch");
  copy_patch(P.patch, r);
  r.uv = P.uv;
  r.boundary_vertices = static_cast<int32_t>(P.boundary.size());
  r.flipped_faces = P.flips.flipped;
  r.degenerate_faces = P.flips.degenerate;
  progress.finish("patch parameterization");
  return r;
}

}  // namespace locus
