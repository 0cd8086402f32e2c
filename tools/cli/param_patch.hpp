// `locus param MESH --center V --fraction f [-o patch.obj] --json`: the patch
// mode of `locus param` (cmd_param.cpp dispatches to it): harmonic
// parameterization of a BFS patch from the GLOBAL factor of the regularized
// cotan Laplacian (thesis §4.4, eq. 4.6; pipelines/include/locus/pipelines/param/patch_param.hpp).
// Implemented in cmd_param_patch.cpp.
#pragma once
#include <cstdint>
#include <string>

#include "tools/cli/cli_common.hpp"

namespace locus::cli {

// boundary: "neumann" (eq. 4.6, pipelines/patch_param) or "circle" (boundary
// fixed on a circle, the patch's factor by the factor-once update,
// pipelines/patch_param_circle). cache: --save / --load of the global factor
// (cli_common.hpp, factor_or_load).
int run_param_patch(const CommonOptions& opt, int32_t center, double fraction, const std::string& boundary,
                    const FactorCacheOptions& cache, const RunContext& ctx);

}  // namespace locus::cli
