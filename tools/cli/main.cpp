// The `locus` command-line tool: command dispatch. Each command lives in its
// own file (cmd_<name>.cpp) and registers itself here; the grammar, exit
// statuses and shared helpers are in cli_common.
#include "tools/cli/cli_common.hpp"

int main(int argc, char** argv) {
  locus::cli::CommandTable table("locus", "locus: factor a mesh operator once, then solve locally");
  locus::cli::register_info_command(table);
  locus::cli::register_factor_command(table);
  return table.run(argc, argv);
}
