// The host program's process state around METIS. locus compiles
// METIS with rand()/srand() and signal()/raise() renamed (cmake/metis.cmake):
// an embedding program that calls rand() sees the same sequence whether or not
// locus ran, rand/srand in the process are the C library's (ctest
// metis_no_process_symbols checks liblocus.a too), and the host's SIGTERM/SIGABRT
// handlers stay installed while orderings run, in parallel or not.
#include <dlfcn.h>
#include <metis.h>
#include <signal.h>

#include <doctest/doctest.h>

#include <atomic>
#include <cstdlib>
#include <thread>
#include <vector>

#include "locus/kernels/order/ordering.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

// The METIS orderings (the default for these sizes is AMD, which draws nothing).
OrderingOptions metis() {
  OrderingOptions o;
  o.method = OrderingOptions::Method::Metis;
  return o;
}

std::vector<int> draws(int count) {
  std::vector<int> v(static_cast<size_t>(count));
  for (int& x : v) x = std::rand();
  return v;
}

}  // namespace

TEST_CASE("host rand: the program's sequence continues as if no ordering had run") {
  const CscMatrix a = test::grid_laplacian(150, 140, 0.01);  // above the split size: two halves at once
  const CscMatrix b = test::random_spd(3000, 5, 3);          // below it: one METIS_NodeND call
  constexpr unsigned seed = 12345;
  // The reference: srand(seed) and nothing from locus in between.
  std::srand(seed);
  const std::vector<int> ref = draws(300);

  std::srand(seed);
  std::vector<int> got = draws(100);
  RunContext two;
  two.threads = 2;
  const Ordering oa = order_matrix(a, metis(), two);
  const std::vector<int> mid = draws(100);
  got.insert(got.end(), mid.begin(), mid.end());
  const Ordering ob = order_matrix(b, metis());
  const std::vector<int> tail = draws(100);
  got.insert(got.end(), tail.begin(), tail.end());
  CHECK(got == ref);
  CHECK(oa.perm.size() == a.ncols);
  CHECK(ob.perm.size() == b.ncols);

  // A host thread drawing while orderings run on other threads: the C library's
  // generator has no other client, so the host still gets exactly its sequence.
  std::srand(seed);
  std::vector<int> host;
  std::thread t1([&] { order_matrix(a, metis(), two); });
  std::thread t2([&] { order_matrix(b, metis()); });
  std::thread drawer([&] { host = draws(300); });
  t1.join();
  t2.join();
  drawer.join();
  CHECK(host == ref);

  // And seeding the host's generator does not change locus' orderings.
  std::srand(1);
  CHECK(order_matrix(a, metis(), two).perm == oa.perm);
  CHECK(order_matrix(b, metis()).perm == ob.perm);
}

TEST_CASE("host rand: rand and srand in the process are the C library's") {
  void* libc = dlopen("libc.so.6", RTLD_LAZY | RTLD_NOLOAD);
  REQUIRE(libc != nullptr);
  CHECK(dlsym(RTLD_DEFAULT, "rand") == dlsym(libc, "rand"));
  CHECK(dlsym(RTLD_DEFAULT, "srand") == dlsym(libc, "srand"));
  // The renamed functions METIS calls are hidden: no other library can bind to them.
  CHECK(dlsym(RTLD_DEFAULT, "locus_metis_rand") == nullptr);
  CHECK(dlsym(RTLD_DEFAULT, "locus_metis_srand") == nullptr);
  dlclose(libc);
}

namespace {
std::atomic<int> g_host_signals{0};
extern "C" void host_handler(int) { ++g_host_signals; }

bool host_handler_installed(int sig) {
  struct sigaction sa {};
  sigaction(sig, nullptr, &sa);
  return sa.sa_handler == host_handler;
}
}  // namespace

TEST_CASE("host signals: the host's SIGTERM and SIGABRT handlers stay installed during orderings") {
  const CscMatrix a = test::grid_laplacian(150, 140, 0.01);  // split: two METIS calls at once
  struct sigaction mine {}, old_term {}, old_abrt {};
  mine.sa_handler = host_handler;
  sigemptyset(&mine.sa_mask);
  sigaction(SIGTERM, &mine, &old_term);
  sigaction(SIGABRT, &mine, &old_abrt);
  std::atomic<bool> stop{false};
  bool changed = false;
  std::thread watcher([&] {  // samples the handlers while METIS runs
    while (!stop)
      if (!host_handler_installed(SIGTERM) || !host_handler_installed(SIGABRT)) changed = true;
  });
  RunContext two;
  two.threads = 2;
  for (int round = 0; round < 4; ++round) {
    std::thread t([&] { order_matrix(a, metis(), two); });
    order_matrix(a, metis(), two);
    t.join();
  }
  stop = true;
  watcher.join();
  CHECK_FALSE(changed);
  CHECK(host_handler_installed(SIGTERM));
  CHECK(host_handler_installed(SIGABRT));
  // A SIGTERM to the host after locus ran reaches the host's handler.
  raise(SIGTERM);
  CHECK(g_host_signals.load() == 1);
  sigaction(SIGTERM, &old_term, nullptr);
  sigaction(SIGABRT, &old_abrt, nullptr);
}

TEST_CASE("host signals: a METIS error raised inside METIS returns an error status, with no signal") {
  // GKlib reports this error with raise(SIGTERM); renamed, it returns to the
  // METIS call, which reports METIS_ERROR. (nparts = 0 is rejected by the
  // partitioner that METIS_PartMeshNodal calls; its message to stdout is dropped:
  // METIS' printf family is renamed, cmake/metis.cmake.)
  struct sigaction mine {}, old_term {};
  mine.sa_handler = host_handler;
  sigemptyset(&mine.sa_mask);
  sigaction(SIGTERM, &mine, &old_term);
  g_host_signals = 0;
  idx_t ne = 2, nn = 4, nparts = 0;
  idx_t eptr[] = {0, 3, 6}, eind[] = {0, 1, 2, 1, 3, 2};
  idx_t objval = 0, epart[2], npart[4];
  const int rc = METIS_PartMeshNodal(&ne, &nn, eptr, eind, nullptr, nullptr, &nparts, nullptr, nullptr, &objval,
                                     epart, npart);
  CHECK(rc == METIS_ERROR);
  CHECK(g_host_signals.load() == 0);  // no SIGTERM reached the process
  CHECK(host_handler_installed(SIGTERM));
  sigaction(SIGTERM, &old_term, nullptr);
}
