// Session queries of Algorithm 1 (thesis chapter 2): the
// perfect Laplacian of the Session's mesh (`locus perfect-laplacian`) and the
// self-supporting surface near it (§2.6, eq. 2.12; `locus selfsupport`).
//
// Both iterate a numeric refactorization of one pattern per step, so there is
// nothing to cache across queries: the Session contributes its checked mesh, and
// the one-shot forms (perfect_laplacian_of, self_supporting_of) take any polygon mesh.
// Results are on a copy; the Session's positions do not change.
#include <cmath>
#include <string>

#include "field_copy.hpp"
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"
#include "locus/pipelines/laplacian/self_supporting.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {

using namespace session_detail;

namespace {

void check_iteration(int32_t max_iterations, double eps, const char* who) {
  if (max_iterations < 1) fail(ErrorCode::BadUsage, std::string(who) + ": max_iterations must be >= 1");
  if (!(eps > 0) || !std::isfinite(eps)) fail(ErrorCode::BadUsage, std::string(who) + ": eps must be a finite positive number");
}

std::vector<int32_t> interleave_edges(const std::vector<int32_t>& e0, const std::vector<int32_t>& e1) {
  std::vector<int32_t> e(2 * e0.size());
  for (size_t k = 0; k < e0.size(); ++k) {
    e[2 * k] = e0[k];
    e[2 * k + 1] = e1[k];
  }
  return e;
}

// Coords (x, y[, z] columns) to 3 interleaved doubles per vertex; z = 0 when absent.
std::vector<double> interleave_xyz(const Coords& p, int32_t nv) {
  std::vector<double> xyz(3 * static_cast<size_t>(nv), 0.0);
  for (size_t c = 0; c < 3 && c < p.size(); ++c)
    for (int32_t i = 0; i < nv && static_cast<size_t>(i) < p[c].size(); ++i) xyz[3 * static_cast<size_t>(i) + c] = p[c][i];
  return xyz;
}

}  // namespace

PerfectLaplacianOutput Session::perfect_laplacian(const PerfectLaplacianRequest& req, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  return perfect_laplacian_of(s->polygons ? *s->polygons : s->mesh, req, ctx);  // a polygon mesh as given (session.hpp)
}

SelfSupportOutput Session::self_supporting(const SelfSupportRequest& req, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  return self_supporting_of(s->polygons ? *s->polygons : s->mesh, req, ctx);  // a polygon mesh as given (session.hpp)
}

PerfectLaplacianOutput perfect_laplacian_of(const Mesh& mesh, const PerfectLaplacianRequest& req, const RunContext& ctx) {
  check_iteration(req.max_iterations, req.eps, "perfect_laplacian");
  MeshPerfectLaplacianOptions o;
  o.planar = req.planar;
  o.iteration.max_iterations = req.max_iterations;
  o.iteration.eps = req.eps;
  o.iteration.method = req.newton ? PerfectLaplacianMethod::newton : PerfectLaplacianMethod::multiplicative;
  const CallProgress progress(ctx, false);  // iterations end early when they converge: finish() reports 1
  const MeshPerfectLaplacianResult R = locus::perfect_laplacian(mesh, o, progress.query());
  PerfectLaplacianOutput r;
  r.edges = interleave_edges(R.e0, R.e1);
  r.weights = R.run.weights;
  r.xyz = interleave_xyz(R.mode == "planar" ? R.run.pos : R.aligned, mesh.num_vertices());
  const Coords& p = R.mode == "planar" ? R.run.pos : R.aligned;
  if (p[2].size() != static_cast<size_t>(mesh.num_vertices()))  // a 2-D embedding: z keeps the input's
    for (int32_t i = 0; i < mesh.num_vertices(); ++i) r.xyz[3 * static_cast<size_t>(i) + 2] = mesh.z[i];
  r.converged = R.run.converged;
  r.iterations = R.run.iterations;
  r.max_displacement_rel = R.max_displacement_rel;
  r.mean_displacement_rel = R.mean_displacement_rel;
  progress.finish("perfect Laplacian");
  return r;
}

SelfSupportOutput self_supporting_of(const Mesh& mesh, const SelfSupportRequest& req, const RunContext& ctx) {
  check_iteration(req.max_iterations, req.eps, "self_supporting");
  if (!(req.load_density > 0) || !std::isfinite(req.load_density))
    fail(ErrorCode::BadUsage, "self_supporting: load_density must be a finite positive number");
  SelfSupportOptions o;
  o.load_density = req.load_density;
  o.iteration.max_iterations = req.max_iterations;
  o.iteration.eps = req.eps;
  const CallProgress progress(ctx, false);
  const SelfSupportResult R = locus::self_supporting(mesh, o, progress.query());
  SelfSupportOutput r;
  r.edges = interleave_edges(R.e0, R.e1);
  r.forces = R.forces;
  r.xyz = interleave_xyz(R.pos, mesh.num_vertices());
  LOCUS_COPY_FIELDS(r, R, converged, iterations, residual_rel);
  progress.finish("self-supporting surface");
  return r;
}

}  // namespace locus
