// summary.json of a `locus run` (or summary-K-of-N.json of one shard): the
// pipeline, its options, every item's line (status, exit status, seconds,
// report, output, error, resumed) in input order, and the counts; --json
// prints it on stdout, otherwise a short table goes to stdout.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/runner/run_options.hpp"

namespace locus::runner {

// Counts of a summary's items and its exit status, written into it: 0 all
// ok, 5 cancelled, 2 every item refused as bad usage, 3 some failed.
int count_summary(Json& summary, bool cancelled, size_t usage_failures);

// The summary of one run (before counting).
Json run_summary(const RunOptions& o, int threads_per_item, const std::vector<std::string>& ignored, bool cancelled,
                 double seconds, Json items);

// Writes the summary atomically to `path` and prints it (--json) or the table.
void write_summary(const RunOptions& o, const Json& summary, const std::filesystem::path& path);

}  // namespace locus::runner
