// Running parallel kernels with a requested number of threads without creating
// a oneTBB arena per call.
//
// oneTBB keeps memory for every arena a worker has joined even after the arena
// is destroyed (measured by the stress run: ~7 KB per arena, 18 -> 88 MB over
// 10,000 short-lived arenas; cf. oneTBB issue #967), so "one task_arena per
// factorization" grows a long-running host process without bound. Instead:
//  * threads <= 0, or equal to the caller's current concurrency: run in place;
//  * otherwise, on an application thread: one arena per (thread, concurrency),
//    created on first use and destroyed when that thread exits;
//  * otherwise (a oneTBB worker asking for another concurrency, which locus'
//    own pipelines never do): a fresh arena for the call.
// Results never depend on the arena: every parallel kernel schedules by size.
#pragma once
#include <memory>
#include <utility>
#include <vector>

#include <tbb/task_arena.h>

namespace locus {

namespace detail {
inline tbb::task_arena& thread_arena(int threads) {
  thread_local std::vector<std::unique_ptr<tbb::task_arena>> arenas;
  if (arenas.size() <= static_cast<size_t>(threads)) arenas.resize(static_cast<size_t>(threads) + 1);
  std::unique_ptr<tbb::task_arena>& a = arenas[static_cast<size_t>(threads)];
  if (!a) a = std::make_unique<tbb::task_arena>(threads);
  return *a;
}
}  // namespace detail

// Calls f() so that oneTBB algorithms inside it use at most `threads` threads
// (<= 0: whatever the caller's arena allows).
template <class F>
void run_with_threads(int threads, F&& f) {
  if (threads <= 0 || threads == tbb::this_task_arena::max_concurrency()) {
    f();
    return;
  }
  // Application threads hold slot 0 of the arenas they enter (or none yet);
  // oneTBB workers never take the slot reserved for them.
  const int slot = tbb::this_task_arena::current_thread_index();
  if (slot == tbb::task_arena::not_initialized || slot == 0) {
    detail::thread_arena(threads).execute(std::forward<F>(f));
    return;
  }
  tbb::task_arena arena(threads);
  arena.execute(std::forward<F>(f));
}

}  // namespace locus
