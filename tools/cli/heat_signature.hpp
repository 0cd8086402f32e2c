// The body shared by `locus adf` (one t) and `locus hks` (several t): both
// report (M - t L_C)^{-1}_ii (pipelines/include/locus/pipelines/heat/adf.hpp) at chosen vertices or all of
// them, with one symbolic factor for every t. Implemented in cmd_hks.cpp.
#pragma once
#include <string>
#include <vector>

#include "tools/cli/cli_common.hpp"

namespace locus::cli {

struct HeatSignatureCliOptions {
  std::vector<std::string> t_texts;  // one TimeSpec per t ("1h2", "0.001")
  std::string vertices;              // --vertices LIST ("" = none)
  bool all = false;                  // --all
  std::string method = "subset";     // subset | selinv | full
  FactorCacheOptions cache;          // --save / --load (one heat factor per t)
  PreviewOptions preview;            // --preview out.png (with --all): one image per t (out-t0.png, ...)
  int preview_t = -1;                // hks --preview-t K: only the K-th t, into out.png (-1 = every t)
};

// `command` is "adf" (property and JSON key `adf`, one t) or "hks" (properties
// hks_0, hks_1, ..., one per t).
int run_heat_signature(const std::string& command, const CommonOptions& opt, const HeatSignatureCliOptions& so,
                       const RunContext& ctx);

// --vertices / --all / --method / --save / --load / --preview, shared by both commands.
void add_heat_signature_options(CLI::App* app, HeatSignatureCliOptions& so);

// The local-solve commands, one file each (cmd_adf.cpp, cmd_hks.cpp,
// cmd_heat.cpp); register_local_solve_commands (cli_common.hpp) adds all three.
void register_adf_command(CommandTable& table);
void register_hks_command(CommandTable& table);
void register_heat_command(CommandTable& table);

}  // namespace locus::cli
