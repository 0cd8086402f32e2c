// One item's child process: this same executable run as
// `locus PIPELINE INPUT [options] --json --threads T -o DIR/STEM.EXT`, stdin
// from /dev/null, stdout and stderr into capture files in DIR. A child
// process isolates what a thread cannot: a crash, an abort or a runaway
// allocation on one hostile file costs that item only, and the memory of a
// finished item goes back to the system.
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tools/runner/job_plan.hpp"
#include "tools/runner/run_options.hpp"

namespace locus::runner {

// The path of the running executable (/proc/self/exe resolved).
std::string self_exe();

// The child's argv for an item: factor writes its output with --save, every
// other pipeline with -o; --preview names DIR/STEM.png.
std::vector<std::string> child_command(const std::string& exe, const RunOptions& o, const Item& it,
                                       const std::filesystem::path& out_dir, int threads_per_item);

// Creates the item's capture files and starts its child in a process group
// of its own, with SIGINT and SIGTERM at their defaults, killed (SIGKILL) when
// the runner dies; returns its pid. Error(Internal) when it cannot be forked
// (an exec failure is the child's exit status 127). The child inherits every
// descriptor not marked close-on-exec (the --out folder's lock among them).
pid_t spawn_item(const std::string& exe, const RunOptions& o, Item& it, const std::filesystem::path& out_dir,
                 int threads_per_item);

}  // namespace locus::runner
