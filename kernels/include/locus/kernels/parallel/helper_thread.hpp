// One persistent helper thread for splitting a single query over two threads.
//
// A query of a few milliseconds cannot afford a std::thread per split (creation
// and join cost tens of microseconds each, and the new thread starts on a cold
// core), nor a oneTBB arena (its workers are shared with the caller's other
// parallel work and may be busy). The helper is created on first use, kept by
// the caller's workspace, sleeps on a futex (std::atomic::wait) between tasks
// and spins briefly before sleeping, so back-to-back splits wake it in
// microseconds.
//
// Usage: run(task) starts task() on the helper; join() waits for it and
// rethrows its exception. The task must stay alive until join(). One task at a
// time; not thread-safe itself (one owner thread). The destructor stops the
// thread (after joining a task still running).
#pragma once
#include <atomic>
#include <cstdint>
#include <exception>
#include <thread>

namespace locus {

class HelperThread {
 public:
  HelperThread() = default;
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;
  ~HelperThread() {
    if (!thread_.joinable()) return;
    if (running_) wait_done();
    stop_ = true;
    posted_.fetch_add(1, std::memory_order_release);
    posted_.notify_one();
    thread_.join();
  }

  template <class Task>
  void run(Task& task) {
    if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
    fn_ = [](void* t) { (*static_cast<Task*>(t))(); };
    arg_ = &task;
    failed_ = nullptr;
    running_ = true;
    posted_.fetch_add(1, std::memory_order_release);
    posted_.notify_one();
  }

  // Waits for the task started by run() (no-op without one); rethrows its exception.
  void join() {
    if (!running_) return;
    wait_done();
    running_ = false;
    if (failed_) {
      std::exception_ptr e = failed_;
      failed_ = nullptr;
      std::rethrow_exception(e);
    }
  }

 private:
  // Spin this many pause rounds (a few microseconds) before sleeping: short,
  // because a spinning thread takes issue slots from the other one where two
  // vCPUs share a core (as on the test machine).
  static constexpr int kSpin = 300;

  static void pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }

  void wait_done() {
    const uint32_t want = posted_.load(std::memory_order_relaxed);
    for (int k = 0; k < kSpin; ++k) {
      if (done_.load(std::memory_order_acquire) == want) return;
      pause();
    }
    for (uint32_t d = done_.load(std::memory_order_acquire); d != want; d = done_.load(std::memory_order_acquire))
      done_.wait(d, std::memory_order_acquire);
  }

  void loop() {
    uint32_t seen = 0;
    for (;;) {
      uint32_t p = posted_.load(std::memory_order_acquire);
      for (int k = 0; k < kSpin && p == seen; ++k) {
        pause();
        p = posted_.load(std::memory_order_acquire);
      }
      while (p == seen) {
        posted_.wait(seen, std::memory_order_acquire);
        p = posted_.load(std::memory_order_acquire);
      }
      seen = p;
      if (stop_) return;
      try {
        fn_(arg_);
      } catch (...) {
        failed_ = std::current_exception();
      }
      done_.store(seen, std::memory_order_release);
      done_.notify_one();
    }
  }

  std::thread thread_;
  std::atomic<uint32_t> posted_{0}, done_{0};
  void (*fn_)(void*) = nullptr;
  void* arg_ = nullptr;
  std::exception_ptr failed_;
  bool running_ = false, stop_ = false;
};

}  // namespace locus
