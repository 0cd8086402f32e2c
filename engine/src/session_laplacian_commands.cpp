// `perfect-laplacian` and `selfsupport` as every front end runs them
// (engine/include/locus/engine/laplacian_requests.hpp): Algorithm 1 of thesis
// chapter 2 (pipelines/.../laplacian/perfect_laplacian.hpp), after the seeded
// noise of §2.5 when asked, and the self-supporting surface of §2.6, eq. 2.12
// (self_supporting.hpp), on the faces as given.
#include <chrono>
#include <cmath>
#include <string>

#include "field_copy.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/laplacian_requests.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"
#include "locus/pipelines/laplacian/self_supporting.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {
namespace session_detail {
namespace {

// Seeded uniform offsets in [-a h, a h] per coordinate, h the mean length of
// the faces' unique edges (splitmix64: the same on every platform).
void add_noise(Mesh& m, double a, uint64_t seed) {
  const Edges E = unique_edges(m);
  double h = 0;
  for (size_t e = 0; e < E.e0.size(); ++e) {
    const int32_t p = E.e0[e], q = E.e1[e];
    h += std::sqrt((m.x[q] - m.x[p]) * (m.x[q] - m.x[p]) + (m.y[q] - m.y[p]) * (m.y[q] - m.y[p]) +
                   (m.z[q] - m.z[p]) * (m.z[q] - m.z[p]));
  }
  if (!E.e0.empty()) h /= static_cast<double>(E.e0.size());
  uint64_t s = seed * 0x2545f4914f6cdd1dULL + 0x6a09e667f3bcc909ULL;
  auto uniform = [&s]() {
    uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  };
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    m.x[v] += a * h * (2 * uniform() - 1);
    m.y[v] += a * h * (2 * uniform() - 1);
    m.z[v] += a * h * (2 * uniform() - 1);
  }
}

std::vector<double> interleaved(const Coords& p) {
  std::vector<double> xyz(3 * p[0].size());
  for (size_t v = 0; v < p[0].size(); ++v) xyz[3 * v] = p[0][v], xyz[3 * v + 1] = p[1][v], xyz[3 * v + 2] = p[2][v];
  return xyz;
}

std::vector<int32_t> edge_pairs(const std::vector<int32_t>& e0, const std::vector<int32_t>& e1) {
  std::vector<int32_t> out(2 * e0.size());
  for (size_t e = 0; e < e0.size(); ++e) out[2 * e] = e0[e], out[2 * e + 1] = e1[e];
  return out;
}

void check_iteration(int32_t iters, double eps) {
  if (iters < 1 || iters > 1000000)
    fail(ErrorCode::BadUsage, "--iters must be in 1..1000000 (got " + std::to_string(iters) + ")");
  if (!(eps > 0) || !std::isfinite(eps))
    fail(ErrorCode::BadUsage, "--eps must be a finite positive number (got " + format_number(eps) + ")");
}

}  // namespace
}  // namespace session_detail

using namespace session_detail;

void check_request(const PerfectLaplacianCommandRequest& req) {
  check_iteration(req.iters, req.eps);
  if (req.method != "newton" && req.method != "multiplicative")
    fail(ErrorCode::BadUsage, "--method must be newton or multiplicative (got '" + req.method + "')");
  if (req.anderson < 0 || req.anderson > 50)
    fail(ErrorCode::BadUsage, "--anderson must be in 0..50 (got " + std::to_string(req.anderson) + ")");
  if (!(req.noise >= 0) || !std::isfinite(req.noise))
    fail(ErrorCode::BadUsage, "--noise must be a finite number >= 0 (got " + format_number(req.noise) + ")");
}

void check_request(const SelfSupportCommandRequest& req) {
  if (req.support != "boundary") fail(ErrorCode::BadUsage, "--support: only 'boundary' is supported");
  if (!(req.load_density > 0) || !std::isfinite(req.load_density))
    fail(ErrorCode::BadUsage, "--load-density must be a finite positive number (got " +
                                  format_number(req.load_density) + ")");
  check_iteration(req.iters, req.eps);
}

PerfectLaplacianCommandReport Session::perfect_laplacian(const PerfectLaplacianCommandRequest& req,
                                                         const RunContext& ctx) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  Mesh mesh = s->polygons ? *s->polygons : s->mesh;
  if (req.noise > 0) add_noise(mesh, req.noise, req.seed);
  MeshPerfectLaplacianOptions mo;
  mo.planar = req.planar;
  mo.iteration.max_iterations = req.iters;
  mo.iteration.eps = req.eps;
  mo.iteration.anderson_depth = req.anderson;
  mo.iteration.drop_decaying = !req.no_active_set;
  mo.iteration.method =
      req.method == "multiplicative" ? PerfectLaplacianMethod::multiplicative : PerfectLaplacianMethod::newton;
  const auto t0 = std::chrono::steady_clock::now();
  const MeshPerfectLaplacianResult R = locus::perfect_laplacian(mesh, mo, ctx);
  PerfectLaplacianCommandReport r;
  r.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const PerfectLaplacianResult& p = R.run;
  r.xyz = interleaved(R.mode == "planar" ? p.pos : R.aligned);
  r.edges = edge_pairs(R.e0, R.e1);
  r.weights = p.weights;
  LOCUS_COPY_FIELDS(r, R, mode, boundary_on_circle, boundary_loops);
  r.pinned_vertices = R.pinned;
  r.converged = p.converged;
  r.iterations = p.iterations;
  r.last_change_rel = p.last_change_rel, r.min_weight = p.min_weight, r.min_positive_weight = p.min_positive_weight;
  r.zero_weights = p.zero_weights, r.weights_at_floor = p.at_floor, r.weights_revived = p.revived;
  r.kkt_rounds = p.kkt_rounds, r.kkt_violation = p.kkt_violation;
  r.max_displacement_rel = R.max_displacement_rel, r.mean_displacement_rel = R.mean_displacement_rel;
  r.align_scale = R.align_scale;
  r.factorizations = p.factorizations, r.hessian_products = p.hessian_products;
  r.order_s = p.order_s, r.analyze_s = p.analyze_s, r.first_iter_s = p.first_iter_s, r.iter_s = p.iter_s;
  r.rhs_s = R.rhs_s;
  return r;
}

SelfSupportCommandReport Session::self_supporting(const SelfSupportCommandRequest& req, const RunContext& ctx) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  SelfSupportOptions o;
  o.support = req.support;
  o.load_density = req.load_density;
  o.iteration.max_iterations = req.iters;
  o.iteration.eps = req.eps;
  const SelfSupportResult f = locus::self_supporting(s->polygons ? *s->polygons : s->mesh, o, ctx);
  SelfSupportCommandReport r;
  r.xyz = interleaved(f.pos);
  r.edges = edge_pairs(f.e0, f.e1);
  LOCUS_COPY_FIELDS(r, f, forces, converged, iterations);
  r.residual_rel = f.residual_rel, r.min_force = f.min_force, r.max_force = f.max_force;
  r.zero_forces = f.zero_forces;
  r.max_displacement_rel = f.max_displacement_rel, r.mean_displacement_rel = f.mean_displacement_rel;
  r.first_iter_s = f.first_iter_s, r.iter_s = f.iter_s, r.total_s = f.total_s;
  return r;
}

}  // namespace locus
