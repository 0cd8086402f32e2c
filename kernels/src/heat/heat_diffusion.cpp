// The prepared heat operator (kernels/include/locus/kernels/heat/heat_diffusion.hpp;
// thesis §3.2, eqs. 3.7, 3.8).
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/core/host_allocator.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"

namespace locus {

HeatDiffusion prepare_heat_diffusion(const CscMatrix& A, HostVector<double> mass, double h, double t,
                                     const RunContext& ctx) {
  HeatDiffusion H;
  H.n = A.ncols;
  H.h = h;
  H.t = t;
  H.mass = std::move(mass);
  BatchStopwatch sw;
  // Progress: ordering, analysis, factorization weighted as in HeatGeodesic (docs/shipping.md).
  const Ordering ord = order_matrix(A, {}, ctx.sub(0.0, 0.75));
  H.order_s = sw.lap();
  ctx.check_cancel();
  auto S = analyze(A, ord, {}, ctx.sub(0.75, 0.80));
  H.analyze_s = sw.lap();
  ctx.check_cancel();
  H.factor = factorize(S, A, ctx.sub(0.80, 1.0));
  H.factor_s = sw.lap();
  return H;
}

namespace {

// The defaults: triangles, manifold, no degenerate faces, no unreferenced vertices.
const MeshRequirements kHeatRequirements{};

void check_time(double t_factor, double t_abs) {
  if (!(t_abs >= 0) || !std::isfinite(t_abs) || (t_abs == 0 && (!(t_factor > 0) || !std::isfinite(t_factor))))
    fail(ErrorCode::BadUsage, "heat diffusion: the diffusion time must be a finite positive number");
}

// The mesh's operator is known to have the pattern of its edges before any value
// is computed, so the ordering and the symbolic analysis of that pattern run
// beside the assembly of the values (the same ordering: it reads the pattern
// only). On a new mesh this is most of the time to a first answer
// (docs/ordering.md, "first answer"). `checked_mass` checks the mesh and returns
// its lumped mass; it runs beside the ordering too, before the assembly (a
// mesh it refuses is refused once the ordering of its edges has finished).
HeatDiffusion prepare_beside(const Mesh& m, const EdgeIncidence& inc, double h, double t,
                             const std::function<HostVector<double>()>& checked_mass, const RunContext& ctx) {
  HeatDiffusion H;
  H.n = m.num_vertices();
  H.h = h;
  H.t = t;
  BatchStopwatch sw;
  const CscMatrix pattern = operator_pattern(m.num_vertices(), inc.edges);
  // The assembly only polls the cancel flag: the ordering reports the progress.
  RunContext quiet = ctx;
  quiet.progress = nullptr;
  ProgressTicker ticker(quiet, "heat operator", 1.0);
  CscMatrix A;
  std::shared_ptr<const SymbolicFactor> S;
  double order_s = 0;
  tbb::parallel_invoke(
      [&] {
        BatchStopwatch osw;
        const Ordering ord = order_matrix(pattern, {}, ctx.sub(0.0, 0.75));
        order_s = osw.lap();
        ctx.check_cancel();
        S = analyze(pattern, ord, {}, ctx.sub(0.75, 0.80));
      },
      [&] {
        const CancelScope scope(ticker);
        H.mass = checked_mass();
        A = heat_operator(m, t, &inc);
      });
  // Beside each other the phases have no separate wall times: the ordering's
  // own is reported, the rest of the overlap counts as analysis.
  const double both_s = sw.lap();
  H.order_s = order_s;
  H.analyze_s = std::max(0.0, both_s - order_s);
  ctx.check_cancel();
  H.factor = factorize(S, A, ctx.sub(0.80, 1.0));
  H.factor_s = sw.lap();
  return H;
}

}  // namespace

HeatDiffusion prepare_heat_diffusion(const Mesh& m, double t_factor, double t_abs, const RunContext& ctx) {
  validate_mesh_arrays(m);
  if (m.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no vertices");
  check_time(t_factor, t_abs);
  BatchStopwatch sw;
  // The edges come first (the pattern); the checks read them too.
  const EdgeIncidence inc = edge_incidence(m);
  const double h = mean_edge_length(m, inc.edges);  // = mean_edge_length(m), the same summation
  const double t = t_abs > 0 ? t_abs : t_factor * h * h;
  const double op_s = sw.lap();
  HeatDiffusion H = prepare_beside(m, inc, h, t, [&] {
    check_requirements(m, kHeatRequirements, analyze_mesh(m, inc));
    return lumped_mass(m);
  }, ctx);
  H.operator_s = op_s;
  return H;
}

HeatDiffusion prepare_heat_diffusion(const Mesh& m, const MeshDerived& d, double t_factor, double t_abs,
                                     const RunContext& ctx) {
  check_derived_of(d, m, "heat diffusion");
  if (m.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no vertices");
  check_time(t_factor, t_abs);
  const double h = d.h;  // mean_edge_length(m), summed in the same order
  const double t = t_abs > 0 ? t_abs : t_factor * h * h;
  return prepare_beside(m, d.incidence, h, t, [&] {
    if (!requirements_checked(d, kHeatRequirements)) check_requirements(m, kHeatRequirements, analyze_mesh(m, d.incidence));
    return d.mass;
  }, ctx);
}

}  // namespace locus
