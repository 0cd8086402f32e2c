// METIS ordering (kernels/ordering): concurrent calls from several threads give
// the orderings of sequential calls (each METIS call draws from a generator of
// its own), the split ordering does not depend on the thread count, and a
// cancel flag stops a caller during METIS without disturbing later orderings.
// The host's rand() is tested in host_rand.cpp.
#include "locus/kernels/order/ordering.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>
#include <vector>

#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

TEST_CASE("ordering: concurrent METIS calls equal sequential ones") {
  const CscMatrix a = test::grid_laplacian(120, 110, 0.01);
  const CscMatrix b = test::random_spd(8000, 5, 3);
  const Ordering ra = order_matrix(a), rb = order_matrix(b);
  for (int round = 0; round < 3; ++round) {
    Ordering ca, cb;
    std::thread t1([&] { ca = order_matrix(a); });
    std::thread t2([&] { cb = order_matrix(b); });
    t1.join();
    t2.join();
    CHECK(ca.perm == ra.perm);
    CHECK(cb.perm == rb.perm);
  }
}

TEST_CASE("ordering: a cancel flag stops the caller; later orderings are unchanged") {
  const CscMatrix a = test::grid_laplacian(300, 300, 0.01);
  const Ordering ref = order_matrix(a);
  std::atomic<bool> cancel{true};
  RunContext ctx;
  ctx.cancel = &cancel;
  try {
    order_matrix(a, {}, ctx);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::Cancelled);
  }
  // Raised while METIS runs: the caller returns after the running METIS call,
  // leaving nothing behind that could disturb the next call.
  cancel = false;
  std::thread raiser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    cancel = true;
  });
  bool cancelled = false;
  try {
    const Ordering o = order_matrix(a, {}, ctx);
    CHECK(o.perm == ref.perm);  // finished before the flag: must be the same ordering
  } catch (const Error& e) {
    cancelled = e.code() == ErrorCode::Cancelled;
    CHECK(cancelled);
  }
  raiser.join();
  CHECK(order_matrix(a).perm == ref.perm);
  cancel = false;
  CHECK(order_matrix(a, {}, ctx).perm == ref.perm);  // a cancel flag that stays down changes nothing
}

TEST_CASE("ordering: the same permutation with 1 and 2 threads; the host's rand() is untouched") {
  const CscMatrix a = test::grid_laplacian(150, 140, 0.01);  // above the split size
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  std::srand(42);
  const int first = std::rand();
  std::srand(42);
  const Ordering o1 = order_matrix(a, {}, one);
  const Ordering o2 = order_matrix(a, {}, two);
  CHECK(std::rand() == first);  // METIS drew from its own generator, not the program's
  CHECK(o1.perm == o2.perm);
  std::vector<int32_t> seen(o1.perm.size(), 0);
  for (size_t k = 0; k < o1.perm.size(); ++k) {
    ++seen[o1.perm[k]];
    CHECK(o1.iperm[o1.perm[k]] == static_cast<int32_t>(k));
  }
  CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<long>(seen.size()));
}
