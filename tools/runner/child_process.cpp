// One item's child process (see child_process.hpp). The child is started with
// fork and exec rather than posix_spawn because it must ask for
// PR_SET_PDEATHSIG itself: it is killed (SIGKILL) when the runner dies, however
// the runner dies, so no orphan goes on computing and writing into the --out
// folder. It inherits the folder's lock descriptor (out_folder_lock.hpp).
#include "tools/runner/child_process.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
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

namespace {

// In the child between fork and exec: only async-signal-safe calls.
[[noreturn]] void exec_child(pid_t runner, const char* exe, char* const* argv, const char* out, const char* err) {
  // Die with the runner, whatever kills it (SIGKILL included): an orphan would
  // go on computing and writing into the folder. If the runner is already gone
  // (it died before prctl took effect), the parent is no longer `runner`.
  if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != runner) ::_exit(127);
  // Own process group: a terminal Ctrl-C reaches the runner only, which forwards
  // exactly one SIGINT (a child's second SIGINT would kill it before it can stop cleanly).
  ::setpgid(0, 0);
  // Default SIGINT and SIGTERM (the child's own handler then turns Ctrl-C into
  // exit 5), also when the runner was started with them ignored.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  ::sigaction(SIGINT, &dfl, nullptr);
  ::sigaction(SIGTERM, &dfl, nullptr);
  const int in_fd = ::open("/dev/null", O_RDONLY);
  const int out_fd = ::open(out, O_WRONLY | O_TRUNC);
  const int err_fd = ::open(err, O_WRONLY | O_TRUNC);
  if (in_fd < 0 || out_fd < 0 || err_fd < 0) ::_exit(127);
  if (::dup2(in_fd, STDIN_FILENO) < 0 || ::dup2(out_fd, STDOUT_FILENO) < 0 || ::dup2(err_fd, STDERR_FILENO) < 0)
    ::_exit(127);
  for (int fd : {in_fd, out_fd, err_fd})
    if (fd > STDERR_FILENO) ::close(fd);
  ::execve(exe, argv, environ);
  static const char kMessage[] = "locus: error: run: cannot execute the locus executable\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  ::_exit(127);
}

}  // namespace

pid_t spawn_item(const std::string& exe, const RunOptions& o, Item& it, const fs::path& out_dir,
                 int threads_per_item) {
  std::vector<std::string> args = child_command(exe, o, it, out_dir, threads_per_item);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  it.out_capture = make_capture(out_dir, it.stem, "stdout");
  it.err_capture = make_capture(out_dir, it.stem, "stderr");
  const pid_t runner = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) exec_child(runner, exe.c_str(), argv.data(), it.out_capture.c_str(), it.err_capture.c_str());
  if (pid < 0) fail(ErrorCode::Internal, "run: cannot start " + exe + ": " + std::strerror(errno));
  ::setpgid(pid, pid);  // also here, so the group exists before the runner may signal it
  return pid;
}

}  // namespace locus::runner
