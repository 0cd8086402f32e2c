// ctest `allocator_unrouted` (README "The allocator": every allocation
// above 64 KB of a geodesic, log map and CVT call goes through the host's
// callbacks). This
// program is the host: it replaces the C library's malloc family for its whole
// process (which a library cannot do, hence its own executable, outside
// locus-tests) and counts every block of 64 KB or more that a call makes, by
// any thread, without coming through the callbacks given to
// locus_set_allocator. On armadillo (26k vertices; without the sample meshes an
// icosphere of 41k) through the C API:
//   - no such block during the first geodesic (which orders and factors), a
//     log map and a CVT;
//   - every block the callbacks handed out is freed after locus_session_destroy,
//     and nothing else is freed through them;
//   - the results equal those of a session without the host's allocator.
// docs/shipping.md "The host's allocator" has the census behind it.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/locus.h"
#include "locus/mesh_io.hpp"
#include "tests/engine/allocator_counting.hpp"

extern "C" void* __libc_malloc(size_t);
extern "C" void* __libc_calloc(size_t, size_t);
extern "C" void* __libc_realloc(void*, size_t);
extern "C" void __libc_free(void*);
extern "C" void* __libc_memalign(size_t, size_t);

namespace {

constexpr size_t kLarge = 64 * 1024;
std::atomic<bool> g_counting{false};
std::atomic<long> g_unrouted{0}, g_routed{0};
thread_local bool t_in_host = false;  // inside the host's callbacks: their malloc is the routed one

void note(size_t n) {
  if (n >= kLarge && !t_in_host && g_counting.load(std::memory_order_relaxed)) g_unrouted.fetch_add(1);
}

}  // namespace

extern "C" void* malloc(size_t n) { note(n); return __libc_malloc(n); }
extern "C" void* calloc(size_t a, size_t b) { note(a * b); return __libc_calloc(a, b); }
extern "C" void* realloc(void* p, size_t n) { note(n); return __libc_realloc(p, n); }
extern "C" void free(void* p) { __libc_free(p); }
extern "C" void* memalign(size_t a, size_t n) { note(n); return __libc_memalign(a, n); }
extern "C" void* aligned_alloc(size_t a, size_t n) { note(n); return __libc_memalign(a, n); }
extern "C" int posix_memalign(void** p, size_t a, size_t n) {
  note(n);
  *p = __libc_memalign(a, n);
  return *p ? 0 : 12;
}

namespace {

using locus::test::CountingAllocator;

void* host_alloc(size_t n, void* user) {
  t_in_host = true;
  void* p = CountingAllocator::alloc(n, user);
  t_in_host = false;
  if (n >= kLarge && g_counting.load()) g_routed.fetch_add(1);
  return p;
}
void host_free(void* p, void* user) { CountingAllocator::free(p, user); }

struct Census {
  long unrouted = 0, routed = 0;
};
template <class F>
Census census(F&& call) {
  g_unrouted = 0;
  g_routed = 0;
  g_counting = true;
  call();
  g_counting = false;
  return {g_unrouted.load(), g_routed.load()};
}

struct Answers {
  std::vector<double> d, uv;
  std::vector<int32_t> labels;
};

locus_session* session_of(const locus::Mesh& m) {
  std::vector<double> xyz;
  for (int32_t i = 0; i < m.num_vertices(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
  locus_session* s = nullptr;
  REQUIRE(locus_session_create(xyz.data(), m.num_vertices(), m.face_vertices.data(), m.num_faces(), &s) == LOCUS_OK);
  return s;
}

}  // namespace

TEST_CASE("allocator: no block of 64 KB or more of a geodesic, log map or CVT bypasses the host's callbacks") {
  // Armadillo once tools/fetch_meshes.sh has run, else an icosphere of the same order of size.
  const char* path = LOCUS_MESH_CACHE_DIR "/armadillo.off";
  const locus::Mesh m = std::filesystem::exists(path) ? locus::read_mesh(path) : locus::make_icosphere(6);
  const int64_t n = m.num_vertices();
  REQUIRE(n > 20000);  // large enough that every per-vertex array is >= 64 KB
  const int32_t sites = 200, iterations = 2;

  Answers want{std::vector<double>(n), std::vector<double>(2 * n), std::vector<int32_t>(n)};
  locus_session* plain = session_of(m);
  REQUIRE(locus_geodesic_distance(plain, 0, want.d.data()) == LOCUS_OK);
  REQUIRE(locus_logmap(plain, 7, 0.1, want.uv.data()) == LOCUS_OK);
  REQUIRE(locus_cvt(plain, sites, iterations, 1, want.labels.data()) == LOCUS_OK);
  locus_session_destroy(plain);

  CountingAllocator c;
  REQUIRE(locus_set_allocator(host_alloc, host_free, &c) == LOCUS_OK);
  locus_session* s = session_of(m);
  Answers got{std::vector<double>(n), std::vector<double>(2 * n), std::vector<int32_t>(n)};
  const Census geodesic = census([&] { REQUIRE(locus_geodesic_distance(s, 0, got.d.data()) == LOCUS_OK); });
  const Census logmap = census([&] { REQUIRE(locus_logmap(s, 7, 0.1, got.uv.data()) == LOCUS_OK); });
  const Census cvt = census([&] { REQUIRE(locus_cvt(s, sites, iterations, 1, got.labels.data()) == LOCUS_OK); });
  MESSAGE("routed / unrouted blocks >= 64 KB: geodesic " << geodesic.routed << " / " << geodesic.unrouted << ", log map "
                                                         << logmap.routed << " / " << logmap.unrouted << ", CVT "
                                                         << cvt.routed << " / " << cvt.unrouted);
  CHECK(geodesic.routed > 0);
  CHECK(logmap.routed > 0);
  CHECK(cvt.routed > 0);
  CHECK(geodesic.unrouted == 0);
  CHECK(logmap.unrouted == 0);  // the log map reuses the geodesic's factors: nothing is ordered
  CHECK(cvt.unrouted == 0);
  CHECK(c.live_blocks() > 0);  // the session's cached factors and meshes
  locus_session_destroy(s);
  REQUIRE(locus_set_allocator(nullptr, nullptr, nullptr) == LOCUS_OK);

  CHECK(c.live_blocks() == 0);
  CHECK(c.allocs == c.frees);
  CHECK(c.foreign_frees == 0);
  CHECK(std::memcmp(got.d.data(), want.d.data(), n * sizeof(double)) == 0);
  CHECK(std::memcmp(got.uv.data(), want.uv.data(), 2 * n * sizeof(double)) == 0);
  CHECK(got.labels == want.labels);
}
