// What a METIS call on this thread does at each of its allocations.
//
// locus compiles METIS itself (cmake/metis.cmake) with malloc/calloc/realloc/
// free renamed to functions of kernels/src/order/metis_memory.cpp: METIS'
// memory comes from the host's allocator (core/include/locus/core/host_allocator.hpp),
// and its allocations, made level by level of its multilevel scheme (every few
// milliseconds at 416k vertices, docs/shipping.md), are where a running METIS
// call can be stopped. Inside a MetisCallScope each allocation ticks the
// scope's progress (a C host's chance to cancel) and, once the cancel flag is
// up, fails: METIS then takes its own out-of-memory path (it longjmps out of
// the call and frees everything it allocated in it) and returns
// METIS_ERROR_MEMORY, which the caller turns into Error(Cancelled) by
// asking stopped(). METIS' messages on that path (fprintf to stderr) are
// renamed away too: locus never writes to stderr.
#pragma once

#include "locus/kernels/parallel/progress_ticker.hpp"

namespace locus {

class MetisCallScope {
 public:
  explicit MetisCallScope(ProgressTicker* ticker);
  ~MetisCallScope();
  MetisCallScope(const MetisCallScope&) = delete;
  MetisCallScope& operator=(const MetisCallScope&) = delete;
  // True once an allocation was refused because the call was cancelled.
  bool stopped() const { return stopped_; }
  // Polled by METIS' allocations: ticks the progress, true when METIS must stop.
  bool should_stop() noexcept;

 private:
  ProgressTicker* ticker_;
  bool stopped_ = false;
  MetisCallScope* outer_;
};

}  // namespace locus
