// The pool of `locus run` (see process_pool.hpp). One thread polls: start
// items while there is room, forward a stop request once, reap finished
// children without blocking, sleep 50 ms when nothing happened.
#include "tools/runner/process_pool.hpp"

#include <sys/wait.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <thread>

#include "locus/error.hpp"
#include "tools/runner/child_process.hpp"
#include "tools/runner/item_report.hpp"
#include "tools/runner/progress_bar.hpp"

namespace locus::runner {
namespace {

std::atomic<int> g_stop{0};  // signal number that asked the runner to stop, 0 = none
static_assert(std::atomic<int>::is_always_lock_free);

// Running children, one slot per job (0 = free): the signal handler may kill them.
constexpr int kMaxJobs = 1024;
std::atomic<pid_t> g_children[kMaxJobs];
static_assert(std::atomic<pid_t>::is_always_lock_free);

// First Ctrl-C: ask to stop (the loop forwards SIGINT to the children once).
// Second: kill the children and die by the signal. Only async-signal-safe calls.
extern "C" void on_stop_signal(int sig) {
  if (g_stop.exchange(sig, std::memory_order_relaxed) == 0) return;
  for (auto& c : g_children) {
    const pid_t pid = c.load(std::memory_order_relaxed);
    if (pid > 0) ::kill(pid, SIGKILL);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void remember_child(pid_t pid) {
  for (auto& c : g_children) {
    pid_t free_slot = 0;
    if (c.compare_exchange_strong(free_slot, pid)) break;
  }
}

void forget_child(pid_t pid) {
  for (auto& c : g_children) {
    pid_t mine = pid;
    if (c.compare_exchange_strong(mine, 0)) break;
  }
}

class Pool {
 public:
  Pool(const PoolJob& job, std::vector<Item>& items, std::vector<Json>& lines)
      : job_(job), o_(*job.options), items_(items), lines_(lines), bar_(items.size()) {
    for (const Json& line : lines_) done_ += line.is_null() ? 0 : 1;
  }

  PoolOutcome run() {
    while (true) {
      const bool stopping = g_stop.load() != 0;
      if (!stopping) start_items();
      if (running_.empty() && (stopping || next_ >= items_.size())) break;
      if (stopping) forward_stop();
      const bool reaped = reap();
      bar_.draw(done_, running_.size(), failed_, elapsed());
      if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    bar_.finish();
    return {g_stop.load() != 0, usage_failures_};
  }

 private:
  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - job_.t0).count();
  }

  void start_items() {
    while (running_.size() < static_cast<size_t>(o_.jobs) && next_ < items_.size()) {
      Item& it = items_[next_];
      if (it.resumed) {
        ++next_;
        continue;
      }
      if (!it.missing.empty()) {
        it.status = "failed";
        it.exit_status = static_cast<int>(ErrorCode::BadInput);
        complete(next_++);
        continue;
      }
      it.start = std::chrono::steady_clock::now();
      it.pid = spawn_item(job_.exe, o_, it, job_.out_dir, job_.threads_per_item);
      remember_child(it.pid);
      running_.push_back(next_++);
    }
  }

  // Asks running children to stop once (a terminal Ctrl-C reached them already;
  // SIGTERM or kill -INT did not), and kills them 10 s later.
  void forward_stop() {
    if (!forwarded_) {
      for (size_t k : running_) ::kill(items_[k].pid, SIGINT);
      forwarded_ = true;
      forwarded_at_ = std::chrono::steady_clock::now();
    } else if (std::chrono::steady_clock::now() - forwarded_at_ > std::chrono::seconds(10)) {
      for (size_t k : running_) ::kill(items_[k].pid, SIGKILL);
      forwarded_at_ = std::chrono::steady_clock::now();
    }
  }

  // Reaps every finished child; true if any.
  bool reap() {
    bool reaped = false;
    for (size_t r = 0; r < running_.size();) {
      Item& it = items_[running_[r]];
      int ws = 0;
      const pid_t got = ::waitpid(it.pid, &ws, WNOHANG);
      if (got == 0 || (got < 0 && errno == EINTR)) {
        ++r;
        continue;
      }
      it.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - it.start).count();
      forget_child(it.pid);
      record_exit(it, got, ws);
      complete(running_[r]);
      running_.erase(running_.begin() + static_cast<std::ptrdiff_t>(r));
      reaped = true;
    }
    return reaped;
  }

  void record_exit(Item& it, pid_t got, int ws) {
    if (got > 0 && WIFEXITED(ws)) {
      it.exit_status = WEXITSTATUS(ws);
      it.status = it.exit_status == 0                                           ? "ok"
                  : it.exit_status == static_cast<int>(ErrorCode::Cancelled) ? "cancelled"
                                                                               : "failed";
      if (it.exit_status == static_cast<int>(ErrorCode::BadUsage)) ++usage_failures_;
    } else if (got > 0 && WIFSIGNALED(ws)) {
      it.signal = WTERMSIG(ws);
      it.status = forwarded_ && (it.signal == SIGINT || it.signal == SIGKILL) ? "cancelled" : "crashed";
    } else {
      it.status = "crashed";
    }
  }

  void complete(size_t k) {
    lines_[k] = finish_item(items_[k], o_, job_.out_dir);
    ++done_;
    const Item& it = items_[k];
    if (it.status == "ok" || it.status == "cancelled") return;
    ++failed_;
    const Json& error = lines_[k]["error"];
    bar_.line(it.input + ": " + it.status + " (" +
              (error.is_null() ? "exit " + std::to_string(it.exit_status) : error.get<std::string>()) + ")");
  }

  const PoolJob& job_;
  const RunOptions& o_;
  std::vector<Item>& items_;
  std::vector<Json>& lines_;
  ProgressBar bar_;
  std::vector<size_t> running_;
  size_t next_ = 0, done_ = 0, failed_ = 0, usage_failures_ = 0;
  bool forwarded_ = false;
  std::chrono::steady_clock::time_point forwarded_at_;
};

}  // namespace

PoolOutcome run_pool(const PoolJob& job, std::vector<Item>& items, std::vector<Json>& lines) {
  g_stop.store(0);
  for (auto& c : g_children) c.store(0);
  auto prev_int = std::signal(SIGINT, on_stop_signal);
  auto prev_term = std::signal(SIGTERM, on_stop_signal);
  const PoolOutcome outcome = Pool(job, items, lines).run();
  std::signal(SIGINT, prev_int);
  std::signal(SIGTERM, prev_term);
  return outcome;
}

}  // namespace locus::runner
