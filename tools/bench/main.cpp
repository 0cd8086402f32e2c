// `locus-bench`: benchmark driver. Each subcommand measures locus against a
// peer on the same input in the same run and reports medians and ratios
// (DESIGN.md "Measuring"); the grammar and exit statuses are the CLI's.
#include "tools/bench/bench_commands.hpp"

int main(int argc, char** argv) {
  locus::cli::CommandTable table("locus-bench", "locus-bench: locus against its peers, medians and ratios");
  locus::bench::register_factor_bench(table);
  return table.run(argc, argv);
}
