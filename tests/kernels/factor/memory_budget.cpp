// Memory budget of a numeric factorization (kernels/include/locus/kernels/factor/memory_budget.hpp).
//
// Oracles: the stored size of L counted from the supernodes' row structures;
// the heap (glibc mallinfo2) while a real factorization runs — its growth is
// what the estimate predicts; /proc/meminfo for the machine's memory. A limit
// below the estimate must raise ResourceLimit before any numeric work: an
// indefinite matrix then reports the limit, not the failed pivot.
#include <doctest/doctest.h>
#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "tests/sanitized.hpp"

using namespace locus;

namespace {

#if LOCUS_TEST_SANITIZED
constexpr bool kHeapCountersWork = false;  // sanitizers replace malloc; mallinfo2 does not see it
#else
constexpr bool kHeapCountersWork = true;
#endif

int64_t heap_in_use() {
  const struct mallinfo2 mi = mallinfo2();
  return static_cast<int64_t>(mi.uordblks + mi.hblkhd);  // small-block arena + mmapped blocks
}

// One worker's Workspace in kernels/src/factor/supernodal_factor.cpp: a row map of n
// int32 and the largest dense update block, counted here from the supernodes.
int64_t per_thread_workspace(const SymbolicFactor& S) {
  int64_t biggest = 1;
  for (int32_t s = 0; s < S.ns; ++s) {
    const int32_t first = S.super_first_col[s], last = S.super_first_col[s + 1];
    for (int64_t u = S.update_ptr[s]; u < S.update_ptr[s + 1]; ++u) {
      const int32_t d = S.update_from[u];
      const int32_t* rd = S.super_rows.data() + S.super_row_ptr[d];
      int64_t below = 0, inside = 0;  // rows of d at or below s's first column; those inside s's columns
      for (int32_t t = S.ncols(d); t < S.nrows(d); ++t)
        if (rd[t] >= first) { ++below; inside += rd[t] < last; }
      biggest = std::max(biggest, below * inside);
    }
  }
  return 4 * static_cast<int64_t>(S.n) + 8 * biggest;
}

CscMatrix test_operator() {
  const Mesh m = make_icosphere(6);  // 40962 vertices
  const double h = mean_edge_length(m);
  return heat_operator(m, h * h);
}

}  // namespace

TEST_CASE("memory estimate: L's storage counted from the supernodes; heap growth of a real factorization") {
  const CscMatrix A = test_operator();
  auto S = analyze(A, order_matrix(A));
  int64_t stored = 0;
  for (int32_t s = 0; s < S->ns; ++s) stored += static_cast<int64_t>(S->nrows(s)) * S->ncols(s);

  for (int threads : {1, 2}) {
    CAPTURE(threads);
    const FactorMemoryEstimate e = estimate_factor_memory(*S, threads);
    CHECK(e.threads == threads);
    CHECK(e.values_bytes == stored * 8);
    CHECK(e.total_bytes == e.values_bytes + e.workspace_bytes + e.solve_bytes);
    RunContext ctx;
    ctx.threads = threads;
    NumericFactor warm = factorize(S, A, ctx);  // thread pool and arenas exist before measuring
    CHECK(e.solve_bytes == static_cast<int64_t>(solve_work_size(warm, kLanes) * sizeof(double)));
    if (!kHeapCountersWork) continue;

    // Sample the heap from another thread while the factorization runs: the
    // peak holds the values and every worker's workspace.
    const int64_t before = heap_in_use();
    std::atomic<bool> done{false};
    std::atomic<int64_t> peak{before};
    std::thread sampler([&] {
      while (!done.load()) {
        const int64_t now = heap_in_use();
        if (now > peak.load()) peak.store(now);
        std::this_thread::sleep_for(std::chrono::microseconds(50));
      }
    });
    NumericFactor F = factorize(S, A, ctx);
    done.store(true);
    sampler.join();
    const int64_t kept = heap_in_use() - before;
    const int64_t grew = peak.load() - before;
    MESSAGE("threads " << threads << ": estimate " << e.values_bytes << " + " << e.workspace_bytes << " B, heap kept " << kept
                       << " B, peak growth " << grew << " B");
    // What stays allocated is L's values: within 1% (allocator rounding, TBB bookkeeping).
    CHECK(std::abs(static_cast<double>(kept - e.values_bytes)) <= 0.01 * static_cast<double>(e.values_bytes));
    // The peak adds the workspace: one copy per worker that took part, at least
    // one and at most `threads` (a worker busy elsewhere never allocates its
    // copy). The sampler may miss a little of it, and never sees more.
    const double one_copy = static_cast<double>(e.workspace_bytes - (threads - 1) * per_thread_workspace(*S));
    CHECK(static_cast<double>(grew) <= 1.02 * static_cast<double>(e.values_bytes + e.workspace_bytes));
    CHECK(static_cast<double>(grew) >= 0.97 * (static_cast<double>(e.values_bytes) + one_copy));
  }
}

TEST_CASE("memory limit: a limit below the estimate raises ResourceLimit before any numeric work") {
  CscMatrix A = test_operator();
  auto S = analyze(A, order_matrix(A));
  RunContext ctx;
  ctx.threads = 2;
  const FactorMemoryEstimate e = estimate_factor_memory(*S, 2);

  // Make the matrix indefinite: a factorization that started would fail with Numerical.
  CscMatrix bad = A;
  for (int32_t j = 0; j < bad.ncols; ++j) bad.values[bad.colptr[j]] = -1.0;  // diagonal entries come first
  for (std::size_t limit : {std::size_t{1}, static_cast<std::size_t>(e.total_bytes - 1)}) {
    CAPTURE(limit);
    ctx.max_memory_bytes = limit;
    try {
      factorize(S, bad, ctx);
      FAIL("no error raised");
    } catch (const Error& err) {
      CHECK(err.code() == ErrorCode::ResourceLimit);
      const std::string msg = err.what();
      CAPTURE(msg);
      CHECK(msg.find("nnz(L) = " + std::to_string(S->nnz_L)) != std::string::npos);
      CHECK(msg.find(std::to_string(e.values_bytes / 8) + " values stored") != std::string::npos);
      CHECK(msg.find(" GiB") != std::string::npos);
      CHECK(msg.find("--max-memory") != std::string::npos);
      CHECK(msg.find("2 threads") != std::string::npos);
    }
  }
  // At the estimate the factorization runs: the indefinite matrix now fails at its pivot.
  ctx.max_memory_bytes = static_cast<std::size_t>(e.total_bytes);
  try {
    factorize(S, bad, ctx);
    FAIL("no error raised");
  } catch (const Error& err) {
    CHECK(err.code() == ErrorCode::Numerical);
  }
  CHECK_NOTHROW(factorize(S, A, ctx));
}

TEST_CASE("memory limit: physical memory agrees with /proc/meminfo; the default is 80% of it") {
  std::ifstream in("/proc/meminfo");
  std::string key;
  int64_t kib = 0;
  while (in >> key) {
    if (key == "MemTotal:") { in >> kib; break; }
    in.ignore(1 << 12, '\n');
  }
  REQUIRE(kib > 0);
  const std::size_t phys = physical_memory_bytes();
  CHECK(phys > 0);
  CHECK(phys <= static_cast<std::size_t>(kib) * 1024 + 4096);  // a cgroup limit can only lower it
  RunContext ctx;
  CHECK(memory_limit_bytes(ctx) == phys / 5 * 4);
  ctx.max_memory_bytes = 12345;
  CHECK(memory_limit_bytes(ctx) == 12345);
}
