// Running parallel kernels with a requested number of threads without creating
// a oneTBB arena per call.
//
// oneTBB keeps memory for every arena a worker has joined even after the arena
// is destroyed (measured by the stress run: ~7 KB per arena, 18 -> 88 MB over
// 10,000 short-lived arenas; a known oneTBB behaviour, reported upstream), so "one task_arena per
// factorization" grows a long-running host process without bound. Instead:
//  * threads <= 0, or equal to the caller's current concurrency: run in place;
//  * otherwise, on an application thread: an arena of that concurrency
//    borrowed from a process-wide pool for the call and returned after it.
//    (Arenas used to be thread_local, one per (thread, concurrency): a host
//    that starts a thread per request created, and leaked inside oneTBB, one
//    arena per thread; and every host thread kept its arenas until it exited.)
//    The pool holds at most as many arenas of a concurrency as calls ever ran
//    at once with it; an idle arena holds no threads (oneTBB's workers leave
//    arenas without work), only its bookkeeping.
//  * otherwise (a oneTBB worker asking for another concurrency, which locus'
//    own pipelines never do): a fresh arena for the call.
// Results never depend on the arena: every parallel kernel schedules by size.
#pragma once
#include <algorithm>
#include <memory>
#include <utility>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

namespace locus {

namespace detail {
// An arena of `threads` concurrency, exclusively the caller's while alive.
class BorrowedArena {
 public:
  explicit BorrowedArena(int threads);
  ~BorrowedArena();
  BorrowedArena(const BorrowedArena&) = delete;
  BorrowedArena& operator=(const BorrowedArena&) = delete;
  tbb::task_arena& get() { return *arena_; }

 private:
  int threads_;
  std::unique_ptr<tbb::task_arena> arena_;
};
}  // namespace detail

// The most threads a oneTBB arena may have in this process: asking for more
// makes oneTBB print a warning on stderr, and cannot be faster.
inline int max_arena_threads() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

// Calls f() so that oneTBB algorithms inside it use at most `threads` threads
// (<= 0: whatever the caller's arena allows; more than max_arena_threads(): that many).
template <class F>
void run_with_threads(int threads, F&& f) {
  threads = std::min(threads, max_arena_threads());
  if (threads <= 0 || threads == tbb::this_task_arena::max_concurrency()) {
    f();
    return;
  }
  // Application threads hold slot 0 of the arenas they enter (or none yet);
  // oneTBB workers never take the slot reserved for them.
  const int slot = tbb::this_task_arena::current_thread_index();
  if (slot == tbb::task_arena::not_initialized || slot == 0) {
    detail::BorrowedArena arena(threads);
    arena.get().execute(std::forward<F>(f));
    return;
  }
  tbb::task_arena arena(threads);
  arena.execute(std::forward<F>(f));
}

}  // namespace locus
