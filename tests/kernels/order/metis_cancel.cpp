// METIS calls stop inside (kernels/include/locus/kernels/order/metis_call.hpp):
// METIS' allocations tick the progress (a C host's chance to cancel: the first
// report comes from inside METIS, nothing else reports), and a cancel raised
// in the middle of the call (here by the host's allocator at its 40th block)
// makes the next allocation fail; METIS' out-of-memory path unwinds, the call
// throws Cancelled, every block METIS took from the host's allocator is given
// back, and the next call gives the same separator as one never cancelled.
// An allocator that refuses is a resource limit, not a crash.
#include <doctest/doctest.h>

#include <atomic>
#include <string>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/error.hpp"
#include "locus/kernels/order/adjacency_graph.hpp"
#include "locus/kernels/order/metis_ordering.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "tests/engine/allocator_counting.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;
using locus::test::CountingAllocator;

namespace {
struct HostAllocatorScope {
  explicit HostAllocatorScope(CountingAllocator& c) { set_host_allocator(CountingAllocator::alloc, CountingAllocator::free, &c); }
  ~HostAllocatorScope() { set_host_allocator(nullptr, nullptr, nullptr); }
};
}  // namespace

TEST_CASE("metis: a cancel raised during METIS_ComputeVertexSeparator stops it inside; its memory is returned") {
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(200, 200, 0.01));
  HostVector<int8_t> want;
  metis_vertex_separator(g, 7, want);
  // The result buffer is a host allocation too: sized before the counting
  // allocator is installed, so every block counted below is METIS' own.
  HostVector<int8_t> part(want.size());

  CountingAllocator c;
  HostAllocatorScope scope(c);
  std::atomic<bool> cancel{false};
  int reports = 0;
  RunContext ctx;
  ctx.cancel = &cancel;
  ctx.progress = [&](double, std::string_view phase) {
    ++reports;
    CHECK(phase == "ordering");
  };
  c.cancel_flag = &cancel;
  c.cancel_after = 40;
  ProgressTicker ticker(ctx, "ordering", 1.0);
  try {
    metis_vertex_separator(g, 7, part, &ticker);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::Cancelled);
  }
  CHECK(reports >= 1);  // ticked by METIS' allocations: nothing else reports
  CHECK(c.allocs == 40);  // the cancel stopped the call at the allocation after it
  CHECK(c.live_blocks() == 0);  // METIS freed what it had allocated when it unwound
  CHECK(c.foreign_frees == 0);

  cancel = false;
  c.cancel_flag = nullptr;
  ctx.progress = nullptr;
  ProgressTicker quiet(ctx, "ordering", 1.0);
  metis_vertex_separator(g, 7, part, &quiet);
  CHECK(part == want);
  CHECK(c.live_blocks() == 0);
}

TEST_CASE("metis: an allocator that refuses is a resource limit naming METIS") {
  const AdjacencyGraph g = adjacency_of(test::grid_laplacian(40, 40, 0.01));
  HostVector<int8_t> part(static_cast<size_t>(g.n()));  // sized before: the blocks counted are METIS'
  CountingAllocator c;
  c.fail_after = 3;
  HostAllocatorScope scope(c);
  try {
    metis_vertex_separator(g, 7, part);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::ResourceLimit);
    CHECK(std::string(e.what()).find("out of memory in METIS_ComputeVertexSeparator") != std::string::npos);
  }
  CHECK(c.refused == 1);
  CHECK(c.live_blocks() == 0);
  CHECK(c.foreign_frees == 0);
}
