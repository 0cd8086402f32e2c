// The prepared heat operator of a triangle mesh (thesis §3.2, eqs. 3.7, 3.8; §3.4):
// one METIS ordering, one symbolic and one numeric factor of M - t L_C, which then
// serves every heat source (heat_batch.hpp solves them 8 at a time).
//
// t = t_factor * h^2 (h = mean edge length; thesis §3.7 uses t = h^2) or an
// absolute t.
// Thread safety: a prepared HeatDiffusion is immutable; solves may run concurrently.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

// The prepared heat operator (immutable after preparation).
struct HeatDiffusion {
  int32_t n = 0;
  double h = 0;  // mean edge length in the operator's metric
  double t = 0;  // diffusion time used
  HostVector<double> mass;  // lumped mass in the operator's metric
  NumericFactor factor;
  double operator_s = 0, order_s = 0, analyze_s = 0, factor_s = 0;
};
// Isotropic operator M - t L_C of m; t = t_abs when t_abs > 0, else t_factor * h^2.
// Requires a manifold triangle mesh without degenerate faces or unreferenced vertices.
HeatDiffusion prepare_heat_diffusion(const Mesh& m, double t_factor, double t_abs, const RunContext& ctx);
// The same with m's derived data (locus/kernels/mesh/mesh_derived.hpp): h and the lumped
// mass are taken from d, and the requirements are checked unless d.checked covers them.
HeatDiffusion prepare_heat_diffusion(const Mesh& m, const MeshDerived& d, double t_factor, double t_abs,
                                     const RunContext& ctx);
// Any operator A = M - t L already built (e.g. on a lifted metric, pipelines/voronoi/cvt_lloyd),
// with its lumped mass, mean edge length and t.
HeatDiffusion prepare_heat_diffusion(const CscMatrix& A, HostVector<double> mass, double h, double t,
                                     const RunContext& ctx);

}  // namespace locus
