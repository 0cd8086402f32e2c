// What summary.json may claim: before it is written, every item's report is
// read back, and a line whose report file no longer holds this item's report
// (another run into the folder replaced or removed it: another input of the
// same file name, or a run of the same input that ended otherwise) loses its
// report, output and preview and becomes "overwritten", a failure. A summary
// lists only files that hold this run's results.
#pragma once
#include <vector>

#include "tools/runner/job_plan.hpp"
#include "tools/runner/run_options.hpp"

namespace locus::runner {

void confirm_reports(std::vector<Json>& lines, const std::vector<Item>& items, const RunOptions& o);

}  // namespace locus::runner
