// `locus run --merge DIR... [--out DIR]`: one summary.json from the shard
// summaries of a split run, in the order of the unsharded run, as if one run
// had done everything.
#pragma once
#include "tools/runner/run_options.hpp"

namespace locus::runner {

// Reads the shard summaries of every folder in o.merge (its
// summary-K-of-N.json files, or else its summary.json) and writes the merged
// summary to o.out/summary.json. Refuses (Error(BadInput)) summaries of
// different pipelines or options and a missing or repeated shard: a partial
// merge would silently drop items. Returns the merged run's exit status.
int merge_summaries(const RunOptions& o);

}  // namespace locus::runner
