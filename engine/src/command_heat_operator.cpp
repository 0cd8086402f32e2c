// The heat operator of the commands that factor their own
// (command_heat_operator.hpp): the requirements of the operator chosen, M -
// tL (thesis §3.3) and its factor, ordered and factored or loaded.
#include "command_heat_operator.hpp"

#include <chrono>
#include <span>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/robust_heat_operators.hpp"

namespace locus {

HeatDiffusion command_heat_operator(const Mesh& mesh, bool robust, const HeatTime& time,
                                   const FactorCacheFiles& files, const RunContext& ctx, FactorCacheReport& cache,
                                   bool factor_once, const MeshDerived* derived,
                                   const std::function<void()>& assembled, bool borrow_mass) {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  if (robust) req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = false;
  if (derived) check_derived_of(*derived, mesh, "command_heat_operator");
  if (!derived || !requirements_checked(*derived, req)) check_requirements(mesh, req);
  if (mesh.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(mesh) + ": the mesh has no vertices");
  const auto t0 = std::chrono::steady_clock::now();
  HeatDiffusion H;
  H.n = mesh.num_vertices();
  H.h = derived ? derived->h : mean_edge_length(mesh);
  H.t = time.resolve(H.h);
  CscMatrix A;
  if (robust) {
    const RobustOperators R = robust_laplacian(mesh);
    A = robust_heat_operator(R, H.t);
    H.mass = R.mass;
  } else {
    A = heat_operator(mesh, H.t, derived ? &derived->incidence : nullptr);
    if (!(borrow_mass && derived && !derived->mass.empty()))
      H.mass = derived && !derived->mass.empty() ? derived->mass : lumped_mass(mesh);
  }
  if (assembled) assembled();
  H.operator_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const FactorRequest request{"heat", H.t, &A};
  Factors F = factor_or_load(files, mesh, std::span<const FactorRequest>(&request, 1), ctx, factor_once);
  H.factor = std::move(F.factors[0]);
  H.order_s = F.order_s;
  H.analyze_s = F.analyze_s;
  H.factor_s = F.numeric_s;
  cache = FactorCacheReport{files.load, files.save, F.load_s, F.save_s};
  return H;
}

}  // namespace locus
