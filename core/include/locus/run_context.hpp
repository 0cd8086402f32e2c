// RunContext — what a long computation needs from its caller: a thread budget,
// a progress callback and a cancel flag (README "Embedding").
// No process-global configuration: everything travels in this object.
#pragma once
#include <atomic>
#include <cstddef>
#include <functional>
#include <string_view>

#include "locus/error.hpp"

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API RunContext {
  int threads = 0;  // worker threads; 0 = all cores (more than the process may use are clamped, with a message)
  // Called with a fraction in [0,1] and a phase name; may be called from worker threads.
  std::function<void(double fraction, std::string_view phase)> progress;
  const std::atomic<bool>* cancel = nullptr;  // raised by the caller to stop promptly
  // Upper bound on the memory a factorization may allocate, checked against the
  // symbolic estimate before any numeric work; 0 = 80% of physical memory.
  std::size_t max_memory_bytes = 0;
  // Diagnostics that are not errors (e.g. a thread count clamped to what the
  // process allows). locus never writes to stderr; without a callback they are dropped.
  std::function<void(std::string_view text)> message;
  // The part [progress_begin, progress_end] of the caller's overall progress
  // that this context's fractions map to (sub() narrows it; README "Cancellation and progress").
  double progress_begin = 0.0, progress_end = 1.0;

  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
  void check_cancel() const {
    if (cancelled()) fail(ErrorCode::Cancelled, "cancelled");
  }
  void report(double fraction, std::string_view phase) const {
    if (progress) progress(progress_begin + fraction * (progress_end - progress_begin), phase);
  }
  void note(std::string_view text) const {
    if (message) message(text);
  }
  // The same context for a phase that covers [begin, end] of this one's progress.
  RunContext sub(double begin, double end) const {
    RunContext c = *this;
    const double span = progress_end - progress_begin;
    c.progress_begin = progress_begin + begin * span;
    c.progress_end = progress_begin + end * span;
    return c;
  }
};

}  // namespace locus
LOCUS_API_END
