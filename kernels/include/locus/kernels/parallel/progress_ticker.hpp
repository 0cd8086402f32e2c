// Throttled progress of one phase, from any number of threads.
//
// A C host cancels by returning nonzero from its progress callback, so the
// reports are its chances to stop: long phases report at least every
// kEvery (20 ms) of work, and never more often. Work is added as it is done
// (add) or the current fraction is re-reported (tick) from places that do
// work without a measure of it (inside a METIS call). The fraction is
// work done / total work, capped at 1.
#pragma once
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>

#include "locus/run_context.hpp"

namespace locus {

class ProgressTicker {
 public:
  static constexpr int64_t kEveryUs = 20000;

  ProgressTicker(const RunContext& ctx, const char* phase, double total_work)
      : ctx_(ctx), phase_(phase), total_(total_work) {}

  // `work` more units done; reports when the last report is kEvery old.
  void add(double work) {
    if (!ctx_.progress) return;
    done_.fetch_add(work, std::memory_order_relaxed);
    tick();
  }
  // Reports the current fraction when the last report is kEvery old.
  void tick() {
    if (!ctx_.progress) return;
    const int64_t now = std::chrono::duration_cast<std::chrono::microseconds>(
                            std::chrono::steady_clock::now().time_since_epoch())
                            .count();
    int64_t last = last_us_.load(std::memory_order_relaxed);
    if (now - last < kEveryUs) return;
    if (!last_us_.compare_exchange_strong(last, now)) return;  // another thread reports this tick
    // Under the lock, never below an earlier report (a reporter preempted
    // between winning the tick and reporting must not send an older fraction).
    std::lock_guard<std::mutex> lock(mu_);
    reported_ = std::max(reported_, fraction());
    ctx_.report(reported_, phase_);
  }
  double fraction() const {
    return total_ > 0 ? std::min(1.0, done_.load(std::memory_order_relaxed) / total_) : 0.0;
  }
  const RunContext& context() const { return ctx_; }

 private:
  const RunContext ctx_;  // a copy: callers pass sub-ranges built on the spot
  const char* phase_;
  double total_;
  std::atomic<double> done_{0.0};
  std::atomic<int64_t> last_us_{0};
  std::mutex mu_;
  double reported_ = 0.0;
};

}  // namespace locus
