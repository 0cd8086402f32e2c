// The heat operator M - t L_C (or the robust operator's M - tL, --operator) of
// `locus cvt`'s cells through the CLI factor cache (--save / --load,
// cli_common.hpp factor_or_load): label "heat" with the resolved t, so a file saved by
// `locus factor --operator heat`, `locus voronoi` or `locus cvt` with the same t
// and mesh loads in any of them.
#pragma once
#include <span>
#include <utility>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/robust_heat_operators.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {

// `robust`: M - tL and the mass of the robust operator (robust_heat_operators.hpp);
// the mesh is then checked only for triangles and finite coordinates.
inline HeatDiffusion heat_diffusion_cached(const FactorCacheOptions& fc, const Mesh& mesh, const TimeSpec& ts,
                                           const RunContext& ctx, Factors& info, bool robust = false) {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  if (robust) req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = false;
  check_requirements(mesh, req);
  if (mesh.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(mesh) + ": the mesh has no vertices");
  Stopwatch sw;
  HeatDiffusion H;
  H.n = mesh.num_vertices();
  H.h = mean_edge_length(mesh);
  H.t = ts.resolve(H.h);
  CscMatrix A;
  if (robust) {
    const RobustOperators R = robust_laplacian(mesh);
    A = robust_heat_operator(R, H.t);
    H.mass = R.mass;
  } else {
    A = heat_operator(mesh, H.t);
    H.mass = lumped_mass(mesh);
  }
  H.operator_s = sw.seconds();
  const FactorRequest request{"heat", H.t, &A};
  info = factor_or_load(fc, mesh, std::span<const FactorRequest>(&request, 1), ctx);
  H.factor = std::move(info.factors[0]);
  info.factors.clear();
  H.order_s = info.order_s;
  H.analyze_s = info.analyze_s;
  H.factor_s = info.numeric_s;
  return H;
}

// The same on a loaded input, with the operator the loader chose (--operator).
inline HeatDiffusion heat_diffusion_cached(const FactorCacheOptions& fc, const Input& in, const TimeSpec& ts,
                                           const RunContext& ctx, Factors& info) {
  return heat_diffusion_cached(fc, in.mesh, ts, ctx, info, in.op.robust);
}

}  // namespace locus::cli
