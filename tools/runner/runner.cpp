// `locus run PIPELINE FILE-OR-FOLDER... [pipeline options] --out DIR [--jobs J]
// [--threads N] [--ext EXT] [--json]`: one pipeline (any locus command) over
// many meshes, each input in a child process of this same executable
// (README "locus run"). This file is the sequence: parse, take the --out
// folder (refusing a folder of other options, removing stale temporaries),
// plan the items, resume, run the pool, check the reports still hold this
// run's results, write the summary.
//
// Exit status: 0 every input succeeded; 3 some input failed (bad file,
// numerical failure or crash: each is reported and skipped, the run goes on);
// 2 bad usage of the runner, or every input refused as bad usage by the
// pipeline (its options are wrong: --sites abc); 5 cancelled. A bad-usage
// refusal of some inputs only (--sites 200 on a 19-vertex mesh) is a failed
// input like any other: the run goes on.
#include "tools/runner/runner.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <system_error>
#include <thread>

#include "locus/error.hpp"
#include "tools/runner/child_process.hpp"
#include "tools/runner/item_report.hpp"
#include "tools/runner/job_plan.hpp"
#include "tools/runner/merge.hpp"
#include "tools/runner/out_files.hpp"
#include "tools/runner/out_folder_lock.hpp"
#include "tools/runner/process_pool.hpp"
#include "tools/runner/report_check.hpp"
#include "tools/runner/resume.hpp"
#include "tools/runner/run_options.hpp"
#include "tools/runner/summary.hpp"

namespace locus::runner {
namespace {

namespace fs = std::filesystem;

void create_out_folder(const std::string& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) usage_error("--out " + out + ": cannot create the folder (" + ec.message() + ")");
}

}  // namespace

int run_pipeline_runner(int argc, char** argv, const std::vector<std::string>& commands) {
  const RunOptions o = parse_run_args(argc, argv, commands);
  const fs::path out_dir = o.out;
  create_out_folder(o.out);
  if (!o.merge.empty()) return merge_summaries(o);
  OutFolderLock folder(out_dir, o);
  std::vector<std::string> ignored;
  std::vector<Item> items = select_shard(expand_inputs(o.inputs, o.recursive, ignored), o.shard, o.shards);
  const int total_threads =
      o.threads > 0 ? o.threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  PoolJob job;
  job.options = &o;
  job.out_dir = out_dir;
  job.exe = self_exe();
  job.threads_per_item = std::max(1, total_threads / o.jobs);
  job.t0 = std::chrono::steady_clock::now();

  std::vector<Json> lines(items.size());
  if (o.resume)
    for (size_t k = 0; k < items.size(); ++k) resume_item(items[k], o, out_dir, lines[k]);
  const PoolOutcome outcome = run_pool(job, items, lines);

  confirm_reports(lines, items, o);
  Json item_list = Json::array();
  for (size_t k = 0; k < items.size(); ++k)
    item_list.push_back(lines[k].is_null() ? unreported_line(items[k]) : lines[k]);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - job.t0).count();
  Json summary = run_summary(o, job.threads_per_item, ignored, outcome.cancelled, seconds, std::move(item_list));
  const int status = count_summary(summary, outcome.cancelled, outcome.usage_failures);
  const fs::path path = summary_path(out_dir, o.shard, o.shards);
  write_summary(o, summary, path);
  folder.clean_up_if_alone(summary["succeeded"].get<size_t>() > 0);
  if (status == static_cast<int>(ErrorCode::BadUsage))
    std::cerr << "locus: error: run: " << o.pipeline << " refused its options on every input (see " << path.string()
              << ")\n";
  if (outcome.cancelled) std::cerr << "locus: error: cancelled\n";
  return status;
}

}  // namespace locus::runner
