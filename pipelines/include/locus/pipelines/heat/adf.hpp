// Auto-diffusion function and heat kernel signature from prefactored heat
// operators (thesis §4.6 "The autodiffusion function", with the heat equation
// of eq. 6.3: (M - t L_C) h_i = e_i).
//
// What is reported (no mass scaling):
//   ADF_t(i) = (A_t^{-1})_ii,   A_t = M - t L_C   (M lumped, L_C negative diagonal)
// the heat left at vertex i after one backward-Euler step of length t from a
// unit amount of heat placed at i (right-hand side e_i, eq. 6.3). The value for
// a unit heat *density* at i, (A_t^{-1} M)_ii, is M_ii * ADF_t(i) (M is diagonal).
// Analytic facts the tests use: ADF_0(i) = 1 / M_ii; d/dt (A_t^{-1})_ii =
// h_i^T L_C h_i < 0 with h_i = A_t^{-1} e_i (L_C is negative semidefinite and h_i
// is not constant), so ADF_t(i) strictly decreases in t; on a closed connected
// mesh ADF_t(i) -> 1 / area as t -> infinity.
// The heat kernel signature HKS(i) = (ADF_t1(i), ADF_t2(i), ...) over several t;
// all heat operators of a mesh share one pattern, hence ONE symbolic factor and
// one etree path per vertex for every t (§4.6).
//
// Methods for the diagonal entries:
//  * Subset: (A^{-1})_ii = e_i^T L^{-T} L^{-1} e_i = ||y||^2 with y = L^{-1} e_i
//    (factor numbering). y is nonzero only on the etree path from i to the root,
//    so one forward walk along that path gives the value: half the work of a
//    subset solve (forward along the path, then backward along the same path).
//  * Selinv: selected inversion (kernels/include/locus/kernels/solve/selected_inversion.hpp, Takahashi
//    recurrences) gives diag(A^{-1}) for ALL vertices in a small multiple of one
//    factorization; for a few chosen vertices it still computes all of them.
//  * Full: a full solve with b = e_i per vertex (the slow reference).
// Queries are independent per vertex: they run in parallel over vertices with
// per-thread workspaces; each value is computed by the same sequential code
// whatever the thread count, so results are deterministic.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"

namespace locus {

// Heat operators M - t L_C for several t: one ordering, one symbolic factor,
// one numeric factorization per t.
struct HeatFactors {
  std::vector<double> t;                           // diffusion times, as given (absolute)
  std::shared_ptr<const SymbolicFactor> symbolic;  // shared by every factor
  std::vector<NumericFactor> factors;              // factors[k]: L L^T = P (M - t[k] L_C) P^T
  double operator_s = 0, order_s = 0, analyze_s = 0, numeric_s = 0;  // seconds; numeric_s sums over t
};

// Throws BadUsage unless every t is finite and > 0; BadInput for meshes the
// operators reject (mesh_operators.hpp); Numerical for a non-SPD operator.
// `ordering`: the fill-reducing ordering's options (default: Auto).
HeatFactors factor_heat_operators(const Mesh& m, std::span<const double> t, const RunContext& ctx = {},
                                  const OrderingOptions& ordering = {});

enum class AdfMethod { Subset, Selinv, Full };
// "subset" / "selinv" / "full"; BadUsage for anything else.
AdfMethod parse_adf_method(const std::string& name);
const char* adf_method_name(AdfMethod m);

// Scratch of one query thread: the sparse solve workspace (all zero between
// calls) and the dense vectors of the full-solve reference.
struct HeatWorkspace {
  SolveWorkspace sparse;
  std::vector<double> dense, work;
};

// (A^{-1})_vv for one vertex by the forward walk (Subset): allocation-free once
// ws is sized (the first call sizes it). BadUsage for v out of range.
double inverse_diagonal_entry(const NumericFactor& F, int32_t v, HeatWorkspace& ws);
// The same walk for several factors sharing one symbolic factor: out[k] = (A_k^{-1})_vv.
void inverse_diagonal_entries(std::span<const NumericFactor> factors, int32_t v, std::span<double> out,
                              HeatWorkspace& ws);
// (A^{-1})_vv by a full solve with b = e_v (reference).
double inverse_diagonal_entry_full(const NumericFactor& F, int32_t v, HeatWorkspace& ws);

// HKS: out[k * nt + j] = ADF_{t_j}(vertices[k]), nt = H.t.size(); `vertices`
// empty means all vertices 0..n-1 (out then holds n * nt values). Parallel over
// vertices; checks ctx's cancel flag between blocks and reports progress.
void heat_kernel_signature(const HeatFactors& H, std::span<const int32_t> vertices, AdfMethod method,
                           std::span<double> out, const RunContext& ctx = {});
// ADF with one factor: out[k] = (A^{-1})_vv for v = vertices[k] (all if empty).
void auto_diffusion(const NumericFactor& F, std::span<const int32_t> vertices, AdfMethod method, std::span<double> out,
                    const RunContext& ctx = {});

}  // namespace locus
