// Memory budget of a numeric factorization (kernels/include/locus/kernels/factor/memory_budget.hpp).
//
// The terms mirror what kernels/src/factor/supernodal_factor.cpp and kernels/src/solve/solve_full.cpp
// allocate; keep them in step when those change (tests/kernels/factor/memory_budget.cpp
// compares the estimate with the heap growth of a real factorization).
#include "locus/kernels/factor/memory_budget.hpp"

#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

#include "locus/error.hpp"

namespace locus {

namespace {

// A cgroup limit file holds a byte count, or "max" (v2) / a huge number (v1) when unlimited.
std::size_t read_cgroup_limit(const char* path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word.empty() || word.find_first_not_of("0123456789") != std::string::npos) return 0;
  try {
    return static_cast<std::size_t>(std::stoull(word));
  } catch (...) {
    return 0;
  }
}

std::string gib(double bytes) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
  return buf;
}

}  // namespace

std::size_t physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  std::size_t bytes = pages > 0 && page > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) : 0;
  // In a container the cgroup, not the machine, decides when the OS kills us.
  for (const char* path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const std::size_t limit = read_cgroup_limit(path);
    if (limit > 0 && (bytes == 0 || limit < bytes)) bytes = limit;
  }
  return bytes;
}

std::size_t memory_limit_bytes(const RunContext& ctx) {
  if (ctx.max_memory_bytes > 0) return ctx.max_memory_bytes;
  const std::size_t phys = physical_memory_bytes();
  return phys > 0 ? phys / 5 * 4 : static_cast<std::size_t>(-1);
}

FactorMemoryEstimate estimate_factor_memory(const SymbolicFactor& S, int threads) {
  FactorMemoryEstimate e;
  e.threads = std::max(1, threads);
  const int64_t n = S.n, ns = S.ns;
  // NumericFactor::values: super_value_ptr[ns] doubles (== nnz_L).
  const int64_t stored = ns > 0 && static_cast<int64_t>(S.super_value_ptr.size()) > ns ? S.super_value_ptr[ns] : S.nnz_L;
  e.values_bytes = stored * static_cast<int64_t>(sizeof(double));
  // Factorizer: one Workspace per worker (row map of n int32, dense update
  // block of max_update_entries doubles), and per supernode the subtree work
  // (double) plus first descendant, child pointers, children, fill cursor and
  // roots (int32 each).
  const int64_t per_thread = n * static_cast<int64_t>(sizeof(int32_t)) +
                             std::max<int64_t>(1, S.max_update_entries) * static_cast<int64_t>(sizeof(double));
  e.workspace_bytes = e.threads * per_thread + ns * static_cast<int64_t>(sizeof(double) + 5 * sizeof(int32_t));
  // solve8: solve_work_size(f, 8) doubles.
  e.solve_bytes = (n + S.max_super_rows) * 8 * static_cast<int64_t>(sizeof(double));
  e.total_bytes = e.values_bytes + e.workspace_bytes + e.solve_bytes;
  return e;
}

void check_factor_memory(const SymbolicFactor& S, const RunContext& ctx) {
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  const FactorMemoryEstimate e = estimate_factor_memory(S, threads);
  const std::size_t limit = memory_limit_bytes(ctx);
  if (static_cast<std::size_t>(e.total_bytes) <= limit) return;
  const std::string which =
      ctx.max_memory_bytes > 0 ? "the memory limit of " + gib(static_cast<double>(limit))
                               : "the default memory limit of " + gib(static_cast<double>(limit)) + " (80% of physical memory)";
  fail(ErrorCode::ResourceLimit,
       "factorization of " + std::to_string(S.n) + " unknowns needs about " + gib(static_cast<double>(e.total_bytes)) +
           " (nnz(L) = " + std::to_string(S.nnz_L) + ", " + std::to_string(e.values_bytes / static_cast<int64_t>(sizeof(double))) +
           " values stored with the supernodes' diagonal blocks: " + gib(static_cast<double>(e.values_bytes)) +
           ", plus workspace for " + std::to_string(e.threads) +
           (e.threads == 1 ? " thread" : " threads") + "), more than " + which +
           "; raise it with --max-memory (RunContext::max_memory_bytes), or use a coarser mesh");
}

}  // namespace locus
