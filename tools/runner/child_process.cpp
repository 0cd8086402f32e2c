// One item's child process (see child_process.hpp).
#include "tools/runner/child_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <system_error>

#include "locus/error.hpp"
#include "tools/runner/out_files.hpp"

extern char** environ;

namespace locus::runner {

namespace fs = std::filesystem;

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("/proc/self/exe") : p.string();
}

std::vector<std::string> child_command(const std::string& exe, const RunOptions& o, const Item& it,
                                       const fs::path& out_dir, int threads_per_item) {
  std::vector<std::string> args = {exe, o.pipeline, it.input};
  args.insert(args.end(), o.pipeline_args.begin(), o.pipeline_args.end());
  args.insert(args.end(), {"--json", "--threads", std::to_string(threads_per_item)});
  if (!o.ext.empty()) {
    const std::string out = output_path(out_dir, it.stem, o.ext).string();
    if (o.pipeline == "factor") {
      args.insert(args.end(), {"--save", out});
    } else {
      args.insert(args.end(), {"-o", out});
    }
  }
  if (o.preview) args.insert(args.end(), {"--preview", preview_path(out_dir, it.stem).string()});
  return args;
}

pid_t spawn_item(const std::string& exe, const RunOptions& o, Item& it, const fs::path& out_dir,
                 int threads_per_item) {
  std::vector<std::string> args = child_command(exe, o, it, out_dir, threads_per_item);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  it.out_capture = make_capture(out_dir, it.stem, "stdout");
  it.err_capture = make_capture(out_dir, it.stem, "stderr");
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, it.out_capture.c_str(), O_WRONLY | O_TRUNC, 0);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, it.err_capture.c_str(), O_WRONLY | O_TRUNC, 0);
  // The child starts with default SIGINT handling (its own handler then turns Ctrl-C into exit 5).
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t def;
  sigemptyset(&def);
  sigaddset(&def, SIGINT);
  sigaddset(&def, SIGTERM);
  posix_spawnattr_setsigdefault(&attr, &def);
  // Own process group: a terminal Ctrl-C reaches the runner only, which forwards
  // exactly one SIGINT (a child's second SIGINT would kill it before it can stop cleanly).
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, exe.c_str(), &fa, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) fail(ErrorCode::Internal, "run: cannot start " + exe + ": " + std::strerror(rc));
  return pid;
}

}  // namespace locus::runner
