// The shared helpers of the `locus` and `locus-bench` tools, one header per
// concern: the command table and common options (cli_command_table.hpp),
// the input and output files (cli_input.hpp), the report (cli_report.hpp),
// heat times (cli_heat_time.hpp), the factored operators (cli_operator.hpp),
// the factor cache (cli_factor_cache.hpp), previews (cli_preview.hpp) and
// numeric helpers (cli_numbers.hpp); and the commands of `locus`.
#pragma once
#include <string>
#include <vector>

#include "tools/cli/cli_command_table.hpp"
#include "tools/cli/cli_factor_cache.hpp"
#include "tools/cli/cli_heat_time.hpp"
#include "tools/cli/cli_input.hpp"
#include "tools/cli/cli_numbers.hpp"
#include "tools/cli/cli_operator.hpp"
#include "tools/cli/cli_preview.hpp"
#include "tools/cli/cli_report.hpp"

namespace locus::cli {

// Commands of the `locus` tool, one file each (tools/cli/cmd_<name>.cpp).
void register_info_command(CommandTable& table);
void register_perfect_laplacian_commands(CommandTable& table);  // perfect-laplacian, param, selfsupport
void register_factor_command(CommandTable& table);
void register_deform_command(CommandTable& table);
void register_local_solve_commands(CommandTable& table);  // adf, hks, heat
void register_voronoi_command(CommandTable& table);
void register_cvt_command(CommandTable& table);
void register_geodesic_commands(CommandTable& table);  // geodesic, logmap


}  // namespace locus::cli
