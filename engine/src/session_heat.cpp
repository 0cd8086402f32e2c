// Session queries of the local-solve pipelines (thesis §4.6):
// auto-diffusion function, heat kernel signature and pairwise heat exchange,
// plus the caches every diffusion pipeline shares (the heat operator per t,
// the regularized Laplacian) and the checks of caller points.
//
// All of them read one cached factor of M - tL per t (State::diffusion): the
// ordering and symbolic analysis are those of prepare_heat_diffusion and of
// the CLI's factor_or_load (order_matrix with default options, then analyze),
// so a Session answers bit for bit what `locus adf|hks|heat` print.
#include <cmath>
#include <string>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/robust_heat_operators.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/pipelines/heat/adf.hpp"
#include "locus/pipelines/heat/heat_exchange.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {
namespace session_detail {

std::shared_ptr<const HeatDiffusion> diffusion(State& s, const HeatQuery& q, const RunContext& ctx) {
  if (q.t != 0.0) {
    if (!(q.t > 0) || !std::isfinite(q.t))
      fail(ErrorCode::BadUsage, "t must be a finite positive number or 0 for t_factor * h^2 (got " +
                                    std::to_string(q.t) + ")");
  } else {
    check_t_factor(diffusion_t_factor(q));
  }
  const double t = q.t > 0 ? q.t : diffusion_t_factor(q) * s.h * s.h;
  return s.diffusion.get(bits_of(t), ctx, [&] {
    ctx.report(0.0, "factor heat operator");
    const std::shared_ptr<const RobustOperators> R = s.robust ? robust_operators(s, ctx) : nullptr;
    const CscMatrix A = R ? robust_heat_operator(*R, t) : heat_operator(s.mesh, t);
    auto H = std::make_shared<HeatDiffusion>();
    H->n = s.mesh.num_vertices();
    H->h = s.h;
    H->t = t;
    if (R)
      H->mass.assign(R->mass.begin(), R->mass.end());
    else
      H->mass.assign(s.derived->mass.begin(), s.derived->mass.end());
    auto S = symbolic_for(s, A, ctx);
    ctx.check_cancel();
    // Inside this phase's progress (the ordering before it takes most of the time, docs/shipping.md).
    H->factor = factorize(S, A, ctx.sub(0.8, 1.0));
    s.counters->numeric.fetch_add(1);
    ctx.report(1.0, "factor heat operator");
    return std::shared_ptr<const HeatDiffusion>(std::move(H));
  });
}

bool diffusion_cached(State& s, const HeatQuery& q) {
  return s.diffusion.contains(bits_of(q.t > 0 ? q.t : diffusion_t_factor(q) * s.h * s.h));
}

std::shared_ptr<const RegularizedLaplacian> laplacian(State& s, const RunContext& ctx) {
  return s.laplacian.get(0, ctx, [&] {
    ctx.report(0.0, "factor Laplacian");
    auto L = std::make_shared<RegularizedLaplacian>();
    L->K = s.robust ? robust_regularized_laplacian(*robust_operators(s, ctx), kLaplacianRegularization)
                    : regularized_laplacian(s.mesh);
    auto S = symbolic_for(s, L->K, ctx);
    ctx.check_cancel();
    L->factor = factorize(S, L->K, ctx.sub(0.8, 1.0));
    s.counters->numeric.fetch_add(1);
    ctx.report(1.0, "factor Laplacian");
    return std::shared_ptr<const RegularizedLaplacian>(std::move(L));
  });
}

SurfacePoint surface_point(const State& s, const MeshPoint& p, const char* what, size_t index) {
  SurfacePoint q;
  q.face = p.face < 0 ? -1 : p.face;
  q.vertex = p.face < 0 ? p.vertex : -1;
  q.bary = p.face < 0 ? std::array<double, 3>{1.0, 0.0, 0.0} : p.bary;
  check_surface_point(s.mesh, q, what, index);  // BadUsage naming the entry: vertex or face out of range, bad weights
  return q;
}

std::vector<SurfacePoint> surface_points(const State& s, ConstView<MeshPoint> p, const char* what) {
  std::vector<SurfacePoint> out;
  out.reserve(p.size());
  for (size_t k = 0; k < p.size(); ++k) out.push_back(surface_point(s, p[k], what, k));
  return out;
}

void check_vertices(const State& s, ConstView<int32_t> v, const char* what) {
  for (size_t k = 0; k < v.size(); ++k)
    check_vertex(s, v[k], (std::string(what) + " " + std::to_string(k) + " is vertex").c_str());
}

namespace {

AdfMethod adf_method(DiagonalMethod m) { return m == DiagonalMethod::SelectedInversion ? AdfMethod::Selinv : AdfMethod::Subset; }

// Values of a heat signature are positive and finite unless the operator is numerically singular.
void check_signature(ConstView<double> values, ConstView<int32_t> vertices, size_t nt, const char* who) {
  for (size_t k = 0; k < values.size(); ++k)
    if (!(std::isfinite(values[k]) && values[k] > 0)) {
      const size_t i = k / nt;
      const int64_t v = vertices.empty() ? static_cast<int64_t>(i) : vertices[i];
      fail(ErrorCode::Numerical, std::string(who) + ": the value at vertex " + std::to_string(v) + " is " +
                                     std::to_string(values[k]) + "; the heat operator is numerically singular");
    }
}

}  // namespace
}  // namespace session_detail

using namespace session_detail;

void Session::prepare_diffusion(const HeatQuery& q, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  diffusion(*s, q, ctx);
}

void Session::prepare_patch_parameterization(const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  laplacian(*s, ctx);
  grower(*s, ctx);
}

int64_t Session::num_edges() const {
  if (has_polygons()) return impl_->polygon_edges;  // the faces as given: the chapter-2 pipelines' edges
  return static_cast<int64_t>(impl_->current()->derived->incidence.edges.e0.size());
}

std::vector<double> Session::auto_diffusion(ConstView<int32_t> vertices, const HeatQuery& q,
                                            DiagonalMethod method, const RunContext& ctx) const {
  return heat_kernel_signature(ConstView<HeatQuery>(&q, 1), vertices, method, ctx);
}

std::vector<double> Session::heat_kernel_signature(ConstView<HeatQuery> times, ConstView<int32_t> vertices,
                                                   DiagonalMethod method, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  if (times.empty()) fail(ErrorCode::BadUsage, "heat_kernel_signature: no diffusion time given");
  check_vertices(*s, vertices, "heat_kernel_signature: entry");
  const size_t nt = times.size();
  const size_t count = vertices.empty() ? static_cast<size_t>(impl_->nv) : vertices.size();
  std::vector<double> out(count * nt), column(count);
  // One cached factor per t (all on one symbolic factor); per t the pipeline's
  // ADF, which computes each value by the same walk as heat_kernel_signature.
  // Progress: time j takes [j, j + 1) / nt of the call, its factor (when not cached) the first 90% of that.
  const CallProgress progress(ctx, false);
  for (size_t j = 0; j < nt; ++j) {
    const RunContext step = progress.query().sub(static_cast<double>(j) / nt, static_cast<double>(j + 1) / nt);
    const CallProgress part(step, !diffusion_cached(*s, times[j]));
    const std::shared_ptr<const HeatDiffusion> H = diffusion(*s, times[j], part.build());
    ctx.check_cancel();
    locus::auto_diffusion(H->factor, vertices, adf_method(method), column, part.query());
    for (size_t k = 0; k < count; ++k) out[k * nt + j] = column[k];
  }
  check_signature(out, vertices, nt, "heat_kernel_signature");
  progress.finish(nt == 1 ? "auto-diffusion" : "heat kernel signature");
  return out;
}

std::vector<double> Session::heat_exchange(ConstView<int32_t> sources, ConstView<int32_t> targets,
                                           const HeatQuery& q, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  if (sources.empty() || targets.empty())
    fail(ErrorCode::BadUsage, "heat_exchange: the source and target sets must not be empty");
  check_vertices(*s, sources, "heat_exchange: source");
  check_vertices(*s, targets, "heat_exchange: target");
  const CallProgress progress(ctx, !diffusion_cached(*s, q));
  const std::shared_ptr<const HeatDiffusion> H = diffusion(*s, q, progress.build());
  ctx.check_cancel();
  std::vector<double> out(targets.size());
  HeatWorkspace ws;
  locus::heat_exchange(H->factor, sources, targets, HeatExchangeMethod::Subset, out, ws);
  for (size_t k = 0; k < out.size(); ++k)
    if (!std::isfinite(out[k]))
      fail(ErrorCode::Numerical, "heat_exchange: the value at target " + std::to_string(targets[k]) + " is " +
                                     std::to_string(out[k]));
  progress.finish("heat exchange");
  return out;
}

}  // namespace locus
