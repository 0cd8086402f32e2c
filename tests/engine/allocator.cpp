// The host's allocator through the C API: locus_set_allocator's
// callbacks receive the large buffers of a geodesic, a log map and a CVT (a
// block the size of a numeric factor's values, computed here from the symbolic
// analysis of the operators' pattern, among them), allocations and frees
// balance once the session is destroyed, nothing is freed that the host did
// not allocate, results equal those without the host's allocator, blocks
// allocated under one allocator are freed by it after the host switched, and
// an allocator that refuses gives LOCUS_BAD_INPUT and leaves the session usable.
#include <doctest/doctest.h>

#include <cstring>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/locus.h"
#include "tests/engine/allocator_counting.hpp"

using namespace locus;
using locus::test::CountingAllocator;

namespace {

locus_session* session_of(const Mesh& m) {
  std::vector<double> xyz;
  for (int32_t i = 0; i < m.num_vertices(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
  locus_session* s = nullptr;
  REQUIRE(locus_session_create(xyz.data(), m.num_vertices(), m.face_vertices.data(), m.num_faces(), &s) == LOCUS_OK);
  return s;
}

// Sets the counting allocator; back to the default at the end of the test case, whatever happened.
struct AllocatorScope {
  explicit AllocatorScope(CountingAllocator& c) { set(c); }
  static void set(CountingAllocator& c) {
    REQUIRE(locus_set_allocator(CountingAllocator::alloc, CountingAllocator::free, &c) == LOCUS_OK);
  }
  ~AllocatorScope() { locus_set_allocator(nullptr, nullptr, nullptr); }
};

struct Answers {
  std::vector<double> d, uv;
  std::vector<int32_t> labels;
};

Answers run(locus_session* s, int64_t n) {
  Answers a{std::vector<double>(n), std::vector<double>(2 * n), std::vector<int32_t>(n)};
  REQUIRE(locus_geodesic_distance(s, 0, a.d.data()) == LOCUS_OK);
  REQUIRE(locus_logmap(s, 7, 0.2, a.uv.data()) == LOCUS_OK);
  REQUIRE(locus_cvt(s, 40, 3, 1, a.labels.data()) == LOCUS_OK);
  return a;
}

bool same(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

TEST_CASE("allocator: geodesic, log map and CVT allocate through the host's callbacks, balanced") {
  const Mesh m = make_icosphere(4);  // 2562 vertices: METIS_NodeND orders it (its memory is routed too)
  const int64_t n = m.num_vertices();
  locus_session* plain = session_of(m);
  const Answers want = run(plain, n);
  locus_session_destroy(plain);

  // The values of one factor of the heat-method operators (every vertex operator has this pattern).
  const CscMatrix K = regularized_laplacian(m);
  const int64_t factor_bytes = analyze(K, order_matrix(K))->super_value_ptr.back() * int64_t(sizeof(double));

  CountingAllocator c;
  {
    AllocatorScope scope(c);
    locus_session* s = session_of(m);
    const Answers got = run(s, n);
    CHECK(same(got.d, want.d));
    CHECK(same(got.uv, want.uv));
    CHECK(got.labels == want.labels);
    CHECK(c.max_block >= factor_bytes);
    CHECK(c.live_blocks() > 0);  // the session's cached factors
    locus_session_destroy(s);
  }
  CHECK(c.allocs > 10);
  CHECK(c.live_blocks() == 0);
  CHECK(c.allocs == c.frees);
  CHECK(c.foreign_frees == 0);
}

TEST_CASE("allocator: blocks are freed by the allocator that made them, after the host switched") {
  const Mesh m = make_icosphere(3);
  const int64_t n = m.num_vertices();
  CountingAllocator first, second;
  AllocatorScope scope(first);
  locus_session* s = session_of(m);
  std::vector<double> d(n);
  REQUIRE(locus_geodesic_distance(s, 0, d.data()) == LOCUS_OK);  // factors cached in `first`'s blocks
  const size_t cached = first.live_blocks();
  CHECK(cached > 0);
  AllocatorScope::set(second);
  std::vector<int32_t> labels(n);
  REQUIRE(locus_cvt(s, 20, 2, 3, labels.data()) == LOCUS_OK);  // a new factor: `second`'s
  CHECK(second.allocs > 0);
  CHECK(first.live_blocks() == cached);
  REQUIRE(locus_set_allocator(nullptr, nullptr, nullptr) == LOCUS_OK);
  locus_session_destroy(s);
  for (CountingAllocator* c : {&first, &second}) {
    CHECK(c->live_blocks() == 0);
    CHECK(c->allocs == c->frees);
    CHECK(c->foreign_frees == 0);
  }
  // One callback without the other is a usage error.
  CHECK(locus_set_allocator(CountingAllocator::alloc, nullptr, &first) == LOCUS_BAD_USAGE);
  CHECK(std::string(locus_last_error_message()).find("both") != std::string::npos);
}

TEST_CASE("allocator: a host allocator that refuses gives LOCUS_BAD_INPUT; the session stays usable") {
  const Mesh m = make_icosphere(3);
  const int64_t n = m.num_vertices();
  CountingAllocator c;
  AllocatorScope scope(c);
  locus_session* s = session_of(m);
  std::vector<double> d(n), want(n);
  c.fail_after = 0;
  CHECK(locus_geodesic_distance(s, 0, d.data()) == LOCUS_BAD_INPUT);
  CHECK(std::string(locus_last_error_message()).find("out of memory") != std::string::npos);
  CHECK(c.refused > 0);
  c.fail_after = -1;
  REQUIRE(locus_geodesic_distance(s, 0, d.data()) == LOCUS_OK);
  locus_session_destroy(s);
  REQUIRE(locus_set_allocator(nullptr, nullptr, nullptr) == LOCUS_OK);
  locus_session* plain = session_of(m);
  REQUIRE(locus_geodesic_distance(plain, 0, want.data()) == LOCUS_OK);
  locus_session_destroy(plain);
  CHECK(same(d, want));
  CHECK(c.live_blocks() == 0);
  CHECK(c.foreign_frees == 0);
}
