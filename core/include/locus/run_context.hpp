// RunContext — what a long computation needs from its caller: a thread budget,
// a progress callback and a cancel flag (DESIGN.md "Pipelines and parallelism").
// No process-global configuration: everything travels in this object.
#pragma once
#include <atomic>
#include <cstddef>
#include <functional>
#include <string_view>

#include "locus/error.hpp"

namespace locus {

struct RunContext {
  int threads = 0;  // worker threads; 0 = all cores
  // Called with a fraction in [0,1] and a phase name; may be called from worker threads.
  std::function<void(double fraction, std::string_view phase)> progress;
  const std::atomic<bool>* cancel = nullptr;  // raised by the caller to stop promptly
  // Upper bound on the memory a factorization may allocate, checked against the
  // symbolic estimate before any numeric work; 0 = 80% of physical memory.
  std::size_t max_memory_bytes = 0;

  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
  void check_cancel() const {
    if (cancelled()) fail(ErrorCode::Cancelled, "cancelled");
  }
  void report(double fraction, std::string_view phase) const {
    if (progress) progress(fraction, phase);
  }
};

}  // namespace locus
