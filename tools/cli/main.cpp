// The `locus` command-line tool: command dispatch. Each command lives in its
// own file (cmd_<name>.cpp) and registers itself here; the grammar, exit
// statuses and shared helpers are in cli_common. `locus run` (one command over
// many meshes) is the runner of tools/runner/, with a grammar of its own.
#include <exception>
#include <iostream>
#include <string>

#include "locus/error.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/runner/runner.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {

// The CLI is its own process, so it may tune the C library's heap (the
// library never does: a host's allocator is the host's). glibc's dynamic
// mmap threshold rises to 32 MB after the first large free, after which the
// cvt's freed 10-30 MB arrays stay resident in the heap; fixing it at 32 MB
// from the start and returning the heap's free top above 1 MB keeps only the
// factor in its own mapping and took ~7 MB off the 416k cvt's peak RSS at
// the same user CPU (docs/cvt.md, "Peak memory"). A 256 KB threshold (every
// large array its own mapping) cost +11% CPU in page faults.
void tune_process_heap() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  tune_process_heap();
  // CommandTable::run maps every error of a command to an exit status; this
  // guard covers building the table itself, so no exception ever leaves main.
  try {
    locus::cli::CommandTable table("locus", "locus: factor a mesh operator once, then solve locally");
    locus::cli::register_info_command(table);
    locus::cli::register_perfect_laplacian_commands(table);
    locus::cli::register_factor_command(table);
    locus::cli::register_deform_command(table);
    locus::cli::register_local_solve_commands(table);
    locus::cli::register_voronoi_command(table);
    locus::cli::register_cvt_command(table);
    locus::cli::register_geodesic_commands(table);
    table.add_listing("run", "Run one command over many meshes: locus run PIPELINE FILE-OR-FOLDER... [options] --out DIR");
    if (argc >= 2 && std::string(argv[1]) == "run") {
      try {
        return locus::runner::run_pipeline_runner(argc, argv, table.names());
      } catch (const locus::Error& e) {
        std::cerr << "locus: error: " << e.what() << "\n";
        return e.exit_status();
      }
    }
    return table.run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "locus: internal error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "locus: internal error\n";
  }
  return 70;
}
