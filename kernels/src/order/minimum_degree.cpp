// AMD orderings (kernels/include/locus/kernels/order/minimum_degree.hpp).
//
// AMD's default controls: aggressive absorption on, and a vertex of degree
// above 10 sqrt(n) set aside as dense and ordered last (never the case for
// mesh graphs above a few dozen vertices).
#include "locus/kernels/order/minimum_degree.hpp"

#include <amd.h>
#include <camd.h>

#include <numeric>
#include <string>

#include "locus/error.hpp"

namespace locus {

std::vector<int32_t> minimum_degree_order(const AdjacencyGraph& g) {
  const int32_t n = g.n();
  std::vector<int32_t> perm(static_cast<size_t>(n));
  if (n == 0) return perm;
  if (g.adj.empty()) {  // no edges: no fill whatever the order
    std::iota(perm.begin(), perm.end(), 0);
    return perm;
  }
  double control[AMD_CONTROL], info[AMD_INFO];
  amd_defaults(control);
  const int rc = amd_order(n, g.xadj.data(), g.adj.data(), perm.data(), control, info);
  if (rc == AMD_OUT_OF_MEMORY)
    fail(ErrorCode::ResourceLimit, "AMD ordering: out of memory on a graph of " + std::to_string(n) + " vertices");
  if (rc != AMD_OK && rc != AMD_OK_BUT_JUMBLED)
    fail(ErrorCode::Internal, "AMD ordering failed with status " + std::to_string(rc) + " on a graph of " +
                                  std::to_string(n) + " vertices");
  return perm;
}

std::vector<int32_t> constrained_minimum_degree_order(const AdjacencyGraph& g, const std::vector<int32_t>& constraint) {
  const int32_t n = g.n();
  std::vector<int32_t> perm(static_cast<size_t>(n));
  if (n == 0) return perm;
  double control[CAMD_CONTROL], info[CAMD_INFO];
  camd_defaults(control);
  const int rc = camd_order(n, g.xadj.data(), g.adj.data(), perm.data(), control, info, constraint.data());
  if (rc == CAMD_OUT_OF_MEMORY)
    fail(ErrorCode::ResourceLimit, "CAMD ordering: out of memory on a graph of " + std::to_string(n) + " vertices");
  if (rc != CAMD_OK && rc != CAMD_OK_BUT_JUMBLED)
    fail(ErrorCode::Internal, "CAMD ordering failed with status " + std::to_string(rc) + " on a graph of " +
                                  std::to_string(n) + " vertices");
  return perm;
}

}  // namespace locus
