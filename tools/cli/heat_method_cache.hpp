// --save / --load for the heat method (geodesic, logmap): its two factors,
// "heat" (M - tL_C, labelled with t) and "poisson" (-L_C + eps M, labelled with
// poisson_rel), on one symbolic factor in one cache file.
#pragma once
#include <optional>
#include <utility>

#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {

// nullopt when neither --save nor --load is given (the pipeline factors itself);
// otherwise the factors, loaded (refused with exit 3 when made for another mesh,
// t or pattern) or factored and saved; `info` gets the timings for the JSON.
inline std::optional<HeatGeodesicFactors> heat_method_factors(const FactorCacheOptions& fc, const Mesh& m,
                                                              const HeatGeodesicOptions& ho, const RunContext& ctx,
                                                              Factors& info) {
  if (fc.save.empty() && fc.load.empty()) return std::nullopt;
  CscMatrix A, P;
  const double t = HeatGeodesic::operators(m, ho, A, P);
  const FactorRequest req[2] = {{"heat", t, &A}, {"poisson", ho.poisson_rel, &P}};
  info = factor_or_load(fc, m, req, ctx);
  return HeatGeodesicFactors{std::move(info.factors[0]), std::move(info.factors[1])};
}

}  // namespace locus::cli
