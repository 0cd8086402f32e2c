// `locus-bench`: benchmark driver. Each subcommand measures locus against a
// peer on the same input in the same run and reports medians and ratios
// (DESIGN.md "Measuring"); the grammar and exit statuses are the CLI's.
#include <exception>
#include <iostream>

#include "tools/bench/bench_commands.hpp"

int main(int argc, char** argv) {
  // CommandTable::run maps every error of a command to an exit status; this
  // guard covers building the table itself, so no exception ever leaves main.
  try {
    locus::cli::CommandTable table("locus-bench", "locus-bench: locus against its peers, medians and ratios");
    locus::bench::register_factor_bench(table);
    locus::bench::register_logmap_bench(table);
    locus::bench::register_logmap_accuracy_bench(table);
    locus::bench::register_geodesic_accuracy_bench(table);
    locus::bench::register_submesh_bench(table);
    locus::bench::register_local_bench(table);
    locus::bench::register_voronoi_bench(table);
    locus::bench::register_stress_bench(table);
    locus::bench::register_cancel_bench(table);
    locus::bench::register_remesh_bench(table);
    locus::bench::register_robust_bench(table);
    locus::bench::register_skinning_bench(table);
    return table.run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "locus-bench: internal error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "locus-bench: internal error\n";
  }
  return 70;
}
