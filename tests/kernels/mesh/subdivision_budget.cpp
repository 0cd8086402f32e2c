// The size of a subdivision before it is made (kernels/include/locus/kernels/mesh/subdivision_budget.hpp):
// 4^times faces, refused as bad input beyond 32-bit face indices and as a
// resource limit beyond the memory limit, naming the counts. Oracle: the face
// count of a subdivision actually made.
#include <doctest/doctest.h>

#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/subdivision_budget.hpp"

using namespace locus;

TEST_CASE("subdivision budget: the estimate's faces are those of the subdivision made") {
  const Mesh m = make_icosphere(1);
  for (int times : {0, 1, 3}) {
    CAPTURE(times);
    CHECK(estimate_subdivision(m.num_faces(), times).faces == subdivide_midpoint(m, times).num_faces());
  }
  CHECK(estimate_subdivision(8, 9).bytes == 8.0 * 262144 * kSubdivisionBytesPerFace);
}

TEST_CASE("subdivision budget: overflowing indices are bad input, too much memory a resource limit") {
  const Mesh m = make_icosphere(4);  // 5120 faces
  RunContext ctx;
  try {
    check_subdivision(m, 9, ctx);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadInput);
    CHECK(std::string(e.what()).find("would make 1342177280 faces") != std::string::npos);
  }
  ctx.max_memory_bytes = 100u << 20;
  try {
    check_subdivision(m, 5, ctx);  // 5.2M faces, 0.68 GB
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::ResourceLimit);
    CHECK(std::string(e.what()).find("5242880 faces") != std::string::npos);
    CHECK(std::string(e.what()).find("memory limit of 0.10 GiB") != std::string::npos);
  }
  CHECK_NOTHROW(check_subdivision(m, 2, ctx));
  CHECK_NOTHROW(check_subdivision(m, 0, ctx));
}
