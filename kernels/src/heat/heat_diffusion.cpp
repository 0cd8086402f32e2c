// The prepared heat operator (kernels/include/locus/kernels/heat/heat_diffusion.hpp;
// thesis §3.2, eqs. 3.7, 3.8).
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/core/host_allocator.hpp"

#include <cmath>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
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

HeatDiffusion prepare_heat_diffusion(const Mesh& m, double t_factor, double t_abs, const RunContext& ctx) {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  check_requirements(m, req);
  if (m.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no vertices");
  if (!(t_abs >= 0) || !std::isfinite(t_abs) || (t_abs == 0 && (!(t_factor > 0) || !std::isfinite(t_factor))))
    fail(ErrorCode::BadUsage, "heat diffusion: the diffusion time must be a finite positive number");
  BatchStopwatch sw;
  const double h = mean_edge_length(m);
  const double t = t_abs > 0 ? t_abs : t_factor * h * h;
  const CscMatrix A = heat_operator(m, t);
  HostVector<double> mass = lumped_mass(m);
  const double op_s = sw.lap();
  HeatDiffusion H = prepare_heat_diffusion(A, std::move(mass), h, t, ctx);
  H.operator_s = op_s;
  return H;
}

HeatDiffusion prepare_heat_diffusion(const Mesh& m, const MeshDerived& d, double t_factor, double t_abs,
                                     const RunContext& ctx) {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  if (!requirements_checked(d, req)) check_requirements(m, req);
  check_derived_of(d, m, "heat diffusion");
  if (m.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no vertices");
  if (!(t_abs >= 0) || !std::isfinite(t_abs) || (t_abs == 0 && (!(t_factor > 0) || !std::isfinite(t_factor))))
    fail(ErrorCode::BadUsage, "heat diffusion: the diffusion time must be a finite positive number");
  BatchStopwatch sw;
  const double h = d.h;  // mean_edge_length(m), summed in the same order
  const double t = t_abs > 0 ? t_abs : t_factor * h * h;
  const CscMatrix A = heat_operator(m, t);
  HostVector<double> mass(d.mass.begin(), d.mass.end());
  const double op_s = sw.lap();
  HeatDiffusion H = prepare_heat_diffusion(A, std::move(mass), h, t, ctx);
  H.operator_s = op_s;
  return H;
}

}  // namespace locus
