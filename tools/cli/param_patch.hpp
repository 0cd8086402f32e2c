// `locus param MESH --center V --fraction f [-o patch.obj] --json`: the patch
// mode of `locus param` (cmd_param.cpp dispatches to it): harmonic
// parameterization of a BFS patch from the GLOBAL factor of the regularized
// cotan Laplacian (thesis §4.4, eq. 4.6), computed by locus::Session::param
// (engine/include/locus/engine/param_request.hpp). Implemented in
// cmd_param_patch.cpp: the patch's output file, JSON and summary.
#pragma once
#include "locus/engine/param_request.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {

int run_param_patch(const CommonOptions& opt, const ParamRequest& req, const RunContext& ctx);

}  // namespace locus::cli
