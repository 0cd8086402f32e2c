// Pairwise heat exchange between two vertex sets from a prefactored heat
// operator (thesis §4.6 "Pairwise heat exchange", heat equation eq. 6.3).
//
// Unit heat sources at every vertex of S (b = sum_{s in S} e_s, repeated
// sources add), one backward-Euler step A x = b with A = M - t L_C; the result
// is x at the targets T: out[k] = x[T[k]] = sum_{s in S} (A^{-1})_{T[k], s}.
// A is symmetric, so the exchange is symmetric: heat(S -> T) summed over T
// equals heat(T -> S) summed over S.
//
// Methods (same values, different work):
//  * Subset: separate subtrees — forward over the etree reach of S only,
//    backward over T and its ancestors only (§4.6, "different subtrees for the
//    forward and back solve"). Exact: the full solve's values at T.
//  * Union: the obvious approach the thesis compares against — one subtree for
//    S ∪ T used for both the forward and the backward solve.
//  * Full: a full solve (reference).
// The plan is built per query (each query has its own pattern); its time is
// part of the query and reported separately.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/pipelines/heat/adf.hpp"

namespace locus {

enum class HeatExchangeMethod { Subset, Union, Full };
// "subset" / "union" / "full"; BadUsage otherwise.
HeatExchangeMethod parse_heat_exchange_method(const std::string& name);
const char* heat_exchange_method_name(HeatExchangeMethod m);

struct HeatExchangeStats {
  int64_t forward_columns = 0, backward_columns = 0;  // factor columns visited (n and n for Full)
  double plan_s = 0, solve_s = 0;
};

// out[k] = heat at targets[k]. BadUsage for empty sets, ids out of range, or a
// wrong output size. Allocation-light: ws is reused across calls.
void heat_exchange(const NumericFactor& F, std::span<const int32_t> sources, std::span<const int32_t> targets,
                   HeatExchangeMethod method, std::span<double> out, HeatWorkspace& ws,
                   HeatExchangeStats* stats = nullptr);

}  // namespace locus
