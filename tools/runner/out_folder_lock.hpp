// Who may write into a --out folder. A folder holds the results of one set of
// options (pipeline, pipeline options, extension, --preview): the first run
// stamps it (DIR/.locus-run.json, written atomically), and a run with other
// options is refused (exit 2) whether the other run is finished or still
// writing, so a report never sits beside another run's output and
// summary.json never lists a file another run replaced. Runs with the same
// options (shards, --resume, two runs at once) share the folder.
//
// Every run holds a shared flock on DIR/.locus-run.lock for its lifetime; its
// children inherit the descriptor, so the lock outlives a killed runner until
// its last child is gone. A run that gets the lock exclusively is alone: every
// temporary file of locus' atomic writes (".NAME.XXXXXX") and every capture
// file left in DIR is then stale, from a run that was killed, and is removed.
// When another run is live nothing is removed (its temporaries look alike);
// the last run out cleans up. A folder where no report says ok is claimed by
// no options: a run whose every input failed withdraws the stamp it wrote.
#pragma once
#include <filesystem>
#include <string>

#include "tools/runner/run_options.hpp"

namespace locus::runner {

class OutFolderLock {
 public:
  // Takes the folder for a run with options `o` (stamping it if it has no
  // stamp) and removes stale temporaries if no other run is live. Throws
  // Error(BadUsage) naming the folder, both option sets and what to do when
  // the folder belongs to other options.
  OutFolderLock(const std::filesystem::path& out_dir, const RunOptions& o);
  ~OutFolderLock();  // releases the lock
  OutFolderLock(const OutFolderLock&) = delete;
  OutFolderLock& operator=(const OutFolderLock&) = delete;

  // At the end of a run (its children reaped, its summary written): if this
  // run is now alone, removes stale temporaries, and withdraws the stamp this
  // run wrote when no report in the folder holds a result (a run whose every
  // input failed, a typo in an option, must not claim the folder). The lock
  // may be dropped by the attempt: the run writes nothing more afterwards.
  void clean_up_if_alone(bool this_run_has_results);

  // The file descriptor of the lock file: children must inherit it.
  int fd() const { return fd_; }

 private:
  std::filesystem::path dir_;
  std::string ext_;
  int fd_ = -1;
  bool stamped_ = false;  // this run wrote the stamp
};

// True for a file name of locus' temporaries in a --out folder: ".NAME.XXXXXX"
// (mkstemp's six letters or digits) where NAME ends in an extension the runner
// or its children write (json png txt stdout stderr ply obj off locus, or `ext`).
bool is_locus_temporary_name(const std::string& name, const std::string& ext);

}  // namespace locus::runner
