// --resume: an item whose report in the --out folder says ok for the same
// input, pipeline, options, extension and --preview is not run again.
#pragma once
#include <filesystem>

#include "tools/runner/job_plan.hpp"
#include "tools/runner/run_options.hpp"

namespace locus::runner {

// True when DIR/STEM.json is an ok report of this item under these options
// (and its output still exists): marks the item ok and resumed and sets its
// summary line. An unreadable report means "run it again".
bool resume_item(Item& it, const RunOptions& o, const std::filesystem::path& out_dir, Json& line);

}  // namespace locus::runner
