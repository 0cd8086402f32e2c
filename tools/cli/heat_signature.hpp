// The front end shared by `locus adf` (one t) and `locus hks` (several t):
// both report (M - t L_C)^{-1}_ii at chosen vertices or all of them through
// locus::Session::adf / hks (engine/include/locus/engine/diffusion_requests.hpp),
// which own the validation and the computation. Implemented in cmd_hks.cpp.
#pragma once
#include <string>
#include <vector>

#include "locus/engine/diffusion_requests.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {

struct HeatSignatureCli {
  std::string command;     // "adf" or "hks"
  AdfRequest adf;          // the request of `adf` ...
  HksRequest hks;          // ... or of `hks`
  std::string vertices;    // --vertices LIST as given ("" = none)
  std::string ts;          // hks --ts LIST as given
  PreviewOptions preview;  // --preview out.png (with --all): one image per t (out-t0.png, ...)
  int preview_t = -1;      // hks --preview-t K: only the K-th t, into out.png (-1 = every t)
};

// Property and JSON key `adf` (one t) or hks_0, hks_1, ... (one per t).
int run_heat_signature(const CommonOptions& opt, HeatSignatureCli& so, const RunContext& ctx);

// --vertices / --all / --method / --save / --load / --preview, bound to the
// request of so.command.
void add_heat_signature_options(CLI::App* app, HeatSignatureCli& so);

// The local-solve commands, one file each (cmd_adf.cpp, cmd_hks.cpp,
// cmd_heat.cpp); register_local_solve_commands (cli_common.hpp) adds all three.
void register_adf_command(CommandTable& table);
void register_hks_command(CommandTable& table);
void register_heat_command(CommandTable& table);

}  // namespace locus::cli
