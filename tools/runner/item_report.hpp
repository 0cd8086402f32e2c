// The report of one item, DIR/STEM.json: {input, pipeline, pipeline_options,
// ext, status (ok | failed | crashed | cancelled), exit_status, signal,
// seconds, output, preview, error (the last "error:" line of the child's
// stderr), stderr, result (the pipeline's JSON, or null)}, and the item's line
// in summary.json.
#pragma once
#include <filesystem>

#include "tools/runner/job_plan.hpp"
#include "tools/runner/run_options.hpp"

namespace locus::runner {

// Reads the finished child's stdout/stderr captures (and removes them),
// writes DIR/STEM.json atomically, returns the item's summary line.
Json finish_item(Item& it, const RunOptions& o, const std::filesystem::path& out_dir);

// The item's line in summary.json, from its report.
Json summary_line(const Item& it, const std::filesystem::path& report_path, const Json& report);

// True when `report` (a parsed DIR/STEM.json) is the report of `input` run
// with these options, whatever its status.
bool report_matches(const Json& report, const std::string& input, const RunOptions& o);

// The line of an item that has no report (not run).
Json unreported_line(const Item& it);

}  // namespace locus::runner
