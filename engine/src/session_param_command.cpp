// `param` as every front end runs it (engine/include/locus/engine/
// param_request.hpp). The disk: the flip-free parameterization of thesis §2.6
// (pipelines/.../laplacian/flipfree_param.hpp) on the faces as given. The
// patch: thesis §4.4 from the factor of the whole mesh's -L_C + eps M — the
// command's own (factor_or_load, with the request's cache files) — and the
// Session's patch grower: the Neumann data of eq. 4.6 and one subset solve
// (pipelines/.../param/patch_param.hpp), or the boundary on a circle with
// the interior's factor by the factor-once update (patch_param_circle.hpp).
#include <chrono>
#include <cmath>
#include <string>

#include "command_clock.hpp"
#include "field_copy.hpp"
#include "locus/engine/factor_store.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/param_request.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/laplacian/flipfree_param.hpp"
#include "locus/pipelines/param/patch_param.hpp"
#include "locus/pipelines/param/patch_param_circle.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {
namespace session_detail {
namespace {

using command_clock::seconds;

void check_uv(const std::vector<double>& uv) {
  for (double v : uv)
    if (!std::isfinite(v)) fail(ErrorCode::Numerical, "param: the patch parameterization is not finite");
}

ParamReport disk(const State& s, const ParamRequest& req, const RunContext& ctx) {
  FlipFreeParamOptions o;
  o.method = parse_param_method(req.method);
  o.iteration.max_iterations = req.iters;
  o.iteration.eps = req.eps;
  const FlipFreeParamResult f = flipfree_param(s.polygons ? *s.polygons : s.mesh, o, ctx);
  ParamReport r;
  r.domain = "disk";
  r.uv = f.uv;
  r.flipped_faces = f.faces.flipped_faces;
  r.degenerate_faces = f.faces.degenerate_faces;
  r.first_flipped_face = f.faces.first_flipped;
  r.min_corner_sin = f.faces.min_corner_sin;
  LOCUS_COPY_FIELDS(r, f, negative_weights, min_weight, converged, iterations, zero_weights, first_iter_s, iter_s);
  r.param_s = f.total_s;
  return r;
}

void circle(const NumericFactor& F, const CscMatrix& K, const PatchGrower& g, int32_t center, int32_t count,
            const RunContext& ctx, ParamReport& r) {
  auto t0 = std::chrono::steady_clock::now();
  CirclePatchParameterizer cp(F, K, g);
  r.prepare_s = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  CirclePatchParam P = cp.parameterize(center, count, ctx);
  r.query_s = seconds(t0);
  check_uv(P.uv);
  r.uv = std::move(P.uv);
  MeshPatch& patch = P.disk.patch;
  r.patch = std::move(patch.mesh);
  r.patch_vertices = patch.vertices;
  r.patch_faces = static_cast<int64_t>(patch.faces.size());
  r.bfs_rings = patch.rings;
  r.boundary_vertices = static_cast<int32_t>(P.disk.boundary.size());
  r.boundary_loops = 1;
  r.holes_filled = P.disk.holes_filled;
  r.vertices_added = P.disk.vertices_added;
  r.euler_characteristic = P.disk.euler_characteristic;
  r.interior_vertices = P.interior;
  r.refinement_steps = P.refinement_steps;
  r.flipped_faces = P.flips.flipped, r.degenerate_faces = P.flips.degenerate, r.orientation = P.flips.orientation;
  r.update_supernodes = P.update.supernodes;
  r.update_supernodes_recomputed = P.update.supernodes_recomputed;
  r.update_columns_recomputed = P.update.columns_recomputed;
  r.update_values_stored = P.update.values_stored;
  r.grow_s = P.grow_s, r.system_s = P.system_s, r.update_s = P.update_s, r.solve_s = P.solve_s;
  r.check_s = P.check_s;
}

void neumann(const NumericFactor& F, const PatchGrower& g, int32_t center, int32_t count, ParamReport& r) {
  PatchWorkspace pws;
  SolveWorkspace ws;
  const auto t0 = std::chrono::steady_clock::now();
  PatchParam P = parameterize_patch(F, g, center, count, pws, ws);
  r.query_s = seconds(t0);
  check_uv(P.uv);
  r.uv = std::move(P.uv);
  r.patch = std::move(P.patch.mesh);
  r.patch_vertices = P.patch.vertices;
  r.patch_faces = static_cast<int64_t>(P.patch.faces.size());
  r.bfs_rings = P.patch.rings;
  r.boundary_vertices = static_cast<int32_t>(P.boundary.size());
  r.boundary_loops = P.boundary_loops;
  r.euler_characteristic = P.euler_characteristic;
  r.flipped_faces = P.flips.flipped, r.degenerate_faces = P.flips.degenerate, r.orientation = P.flips.orientation;
  r.forward_columns = P.forward_columns, r.backward_columns = P.backward_columns;
  r.grow_s = P.grow_s, r.rhs_s = P.rhs_s, r.solve_s = P.solve_s, r.check_s = P.check_s;
}

ParamReport patch(State& s, const ParamRequest& req, const RunContext& ctx) {
  const Mesh& m = s.mesh;
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  check_requirements(m, MeshRequirements{});
  check_vertex(s, req.center, "--center");
  ctx.check_cancel();
  ParamReport r;
  r.domain = "patch";
  r.n = m.num_vertices();
  auto t0 = std::chrono::steady_clock::now();
  const CscMatrix K = regularized_laplacian(m);
  r.operator_s = seconds(t0);
  const FactorRequest freq{"laplacian", 0, &K};
  const FactorCacheFiles files{req.save, req.load};
  const Factors Fs = factor_or_load(files, m, std::span(&freq, 1), ctx);
  r.order_s = Fs.order_s, r.analyze_s = Fs.analyze_s, r.numeric_s = Fs.numeric_s;
  r.etree_height = Fs.symbolic->etree_height;
  r.factor_cache = FactorCacheReport{req.load, req.save, Fs.load_s, Fs.save_s};
  ctx.check_cancel();
  const auto g = grower(s, ctx);
  const int32_t center = static_cast<int32_t>(req.center);
  const int32_t count = patch_vertex_count(m.num_vertices(), req.fraction);
  if (req.boundary == "circle")
    circle(Fs.factors[0], K, *g, center, count, ctx, r);
  else
    neumann(Fs.factors[0], *g, center, count, r);
  return r;
}

}  // namespace
}  // namespace session_detail

using namespace session_detail;

void check_request(const ParamRequest& req) {
  if (req.center < 0) {
    if (req.boundary != "neumann")
      fail(ErrorCode::BadUsage, "param: --boundary applies to the patch mode (--center V)");
    if (!req.save.empty() || !req.load.empty())
      fail(ErrorCode::BadUsage, "param: --save / --load apply to the patch mode (--center V); the disk methods "
                                "factor a new matrix per iteration");
    parse_param_method(req.method);
    if (req.iters < 1 || req.iters > 1000000)
      fail(ErrorCode::BadUsage, "--iters must be in 1..1000000 (got " + std::to_string(req.iters) + ")");
    if (!(req.eps > 0) || !std::isfinite(req.eps))
      fail(ErrorCode::BadUsage, "--eps must be a finite positive number (got " + format_number(req.eps) + ")");
    return;
  }
  if (req.boundary != "neumann" && req.boundary != "circle")
    fail(ErrorCode::BadUsage, "--boundary must be neumann or circle, got '" + req.boundary + "'");
  if (!(req.fraction > 0.0 && req.fraction <= 1.0))
    fail(ErrorCode::BadUsage, "--fraction must be in (0, 1], got " + format_number(req.fraction));
  check_factor_cache_files({req.save, req.load});
}

bool keeps_polygons(const ParamRequest& req) { return req.center < 0; }

ParamReport Session::param(const ParamRequest& req, const RunContext& ctx) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  const CallProgress progress(ctx, false);
  ParamReport r = req.center < 0 ? disk(*s, req, progress.query()) : patch(*s, req, progress.query());
  progress.finish(req.center < 0 ? "disk parameterization" : "patch parameterization");
  return r;
}

}  // namespace locus
