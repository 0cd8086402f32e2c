// `locus run`: one locus command over many meshes, each input in a child
// process (README "locus run"). Not an algorithm of the thesis: the batch tool
// that runs its pipelines over a corpus. The parts, one file each: the
// command line (run_options), the inputs and their names (job_plan), the
// names of its files in --out (out_files), who may write into --out and its
// stale temporaries (out_folder_lock), starting a child (child_process), the
// pool that runs them (process_pool), per-item reports (item_report),
// --resume (resume), what the summary may claim (report_check), summary.json
// (summary), --merge (merge) and the progress bar (progress_bar).
#pragma once
#include <string>
#include <vector>

namespace locus::runner {

// `locus run PIPELINE FILE-OR-FOLDER... [pipeline options] --out DIR ...` or
// `locus run --merge DIR...`. Its grammar differs from the per-mesh commands:
// main() hands it argv when argv[1] is "run"; `commands` are the valid
// PIPELINE names. Returns the exit status; throws locus::Error for bad usage.
int run_pipeline_runner(int argc, char** argv, const std::vector<std::string>& commands);

}  // namespace locus::runner
