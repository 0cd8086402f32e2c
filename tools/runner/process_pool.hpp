// The pool of `locus run`: items run as child processes, J at a time with
// T = max(1, N / J) threads each (N = --threads, default all cores), so the
// machine is not oversubscribed; each finished child's report is written as
// it is reaped.
//
// Ctrl-C (SIGINT) or SIGTERM: no new item starts, running children get SIGINT
// (they stop at their next cancellation check; SIGKILL after 10 s), finished
// results stay, the unfinished items end "cancelled" / "not_run". Children
// run in process groups of their own, so a terminal Ctrl-C reaches them only
// through the runner, once. A second Ctrl-C kills the running children and
// the runner.
#pragma once
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/runner/job_plan.hpp"
#include "tools/runner/run_options.hpp"

namespace locus::runner {

struct PoolJob {
  const RunOptions* options = nullptr;
  std::filesystem::path out_dir;
  std::string exe;  // the executable the children run
  int threads_per_item = 1;
  std::chrono::steady_clock::time_point t0;  // start of the run, for the progress bar's rate
};

struct PoolOutcome {
  bool cancelled = false;     // a stop signal arrived
  size_t usage_failures = 0;  // items whose child exited 2 (bad usage)
};

// Runs every item that is not resumed; lines[k] receives item k's summary
// line when it finishes (resumed items already have theirs).
PoolOutcome run_pool(const PoolJob& job, std::vector<Item>& items, std::vector<Json>& lines);

}  // namespace locus::runner
