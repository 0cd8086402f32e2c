// The flow graph of the batched heat pipelines (heat Voronoi labels, CVT centroids,
// skinning weights): work items solved in parallel, their results merged by one
// serial node, with cancellation, progress and deterministic error reporting.
#pragma once
#include <oneapi/tbb/flow_graph.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>

#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/run_context.hpp"

namespace locus {

// Runs work items 0..count-1 through a oneTBB flow graph inside an arena of
// ctx.threads threads: `solve(i)` (a function_node with unlimited concurrency)
// returns a std::shared_ptr<Msg>, `reduce(msg)` (a serial function_node) merges
// it. Callers make the reduction independent of arrival order (a total order or
// per-item slots merged afterwards in item order), so results do not depend on
// the thread count. Cancellation is polled before each item; no exception leaves
// a node: the first one (lowest item id) is stored and rethrown after
// wait_for_all(). `phase` (nullptr = silent) names the progress reports.
template <class Msg, class Solve, class Reduce>
void run_batch_graph(const RunContext& ctx, int32_t count, Solve&& solve, Reduce&& reduce, const char* phase) {
  if (count <= 0) return;
  struct Item {
    int32_t id = -1;
    std::shared_ptr<Msg> msg;
  };
  std::mutex mu;
  std::exception_ptr err;
  int32_t err_id = INT32_MAX;
  std::atomic<bool> stop{false};
  int32_t done = 0;
  auto record = [&](int32_t id) {
    std::lock_guard<std::mutex> lock(mu);
    if (id < err_id) {
      err_id = id;
      err = std::current_exception();
    }
    stop.store(true);
  };
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  run_with_threads(std::max(1, threads), [&] {  // reused arena: one per call leaks inside oneTBB
    tbb::flow::graph g;
    tbb::flow::function_node<int32_t, Item> work(g, tbb::flow::unlimited, [&](int32_t id) -> Item {
      if (stop.load() || ctx.cancelled()) {
        stop.store(true);
        return {id, nullptr};
      }
      try {
        return {id, solve(id)};
      } catch (...) {
        record(id);
        return {id, nullptr};
      }
    });
    tbb::flow::function_node<Item> merge(g, tbb::flow::serial, [&](const Item& it) -> tbb::flow::continue_msg {
      if (!it.msg || stop.load()) return {};
      try {
        reduce(it.msg);
        ++done;
        if (phase) ctx.report(static_cast<double>(done) / count, phase);
      } catch (...) {
        record(it.id);
      }
      return {};
    });
    tbb::flow::make_edge(work, merge);
    for (int32_t i = 0; i < count; ++i) work.try_put(i);
    g.wait_for_all();
  });
  if (err) std::rethrow_exception(err);
  ctx.check_cancel();
}

}  // namespace locus
