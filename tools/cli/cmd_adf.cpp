// `locus adf MESH [--t T] (--vertices LIST | --all) [--method subset|selinv|full] [-o out.ply] --json`:
// the auto-diffusion function of thesis §4.6, (M - t L_C)^{-1}_ii (no mass
// scaling), through locus::Session::adf. The heat kernel signature with one
// t: the output rules (-o only with --all, PLY property `adf`) and the JSON
// keys are those of `locus hks` (cmd_hks.cpp).
#include "tools/cli/heat_signature.hpp"

namespace locus::cli {

void register_adf_command(CommandTable& table) {
  auto so = std::make_shared<HeatSignatureCli>();
  so->command = "adf";
  CLI::App* app = table.add("adf", "Auto-diffusion function (thesis 4.6): (M - tL)^{-1}_ii at chosen or all vertices",
                            [so](const CommonOptions& opt, const RunContext& ctx) {
                              return run_heat_signature(opt, *so, ctx);
                            });
  app->add_option("--t", so->adf.t, "Diffusion time: absolute (1e-3) or a multiple of h^2 (500h2); default 1h2")
      ->check(non_empty());
  add_heat_signature_options(app, *so);
}

}  // namespace locus::cli
