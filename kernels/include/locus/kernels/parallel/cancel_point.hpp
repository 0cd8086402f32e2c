// Cancel points inside serial kernels that take no RunContext.
//
// Mesh kernels (edge incidence, cotan assembly, gradients) and the phases of
// the symbolic analysis run 50-300 ms each at 416k vertices without a
// RunContext of their own. A caller that wants them interruptible opens a
// CancelScope on its thread with a ProgressTicker; their loops call
// cancel_point(i), which every 4096 iterations ticks the progress (a C host's
// chance to cancel) and throws Error(Cancelled) once the flag is up. Without a
// scope on the thread a cancel point does nothing. Only the thread that
// opened the scope polls: loops that run on oneTBB workers are not cancel
// points (a worker may run tasks of another scope's call).
#pragma once
#include <cstdint>

#include "locus/kernels/parallel/progress_ticker.hpp"

namespace locus {

class CancelScope {
 public:
  explicit CancelScope(ProgressTicker& ticker);
  ~CancelScope();
  CancelScope(const CancelScope&) = delete;
  CancelScope& operator=(const CancelScope&) = delete;

 private:
  ProgressTicker* ticker_;
  CancelScope* outer_;
  friend void cancel_point_poll();
};

// Ticks and checks the innermost scope of this thread (none: nothing).
void cancel_point_poll();

inline void cancel_point(int64_t i) {
  if ((i & 4095) == 0) cancel_point_poll();
}

}  // namespace locus
