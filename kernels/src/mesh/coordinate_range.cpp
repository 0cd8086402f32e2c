// The sizes of mesh the operators hold in double precision (kernels/include/locus/kernels/mesh/coordinate_range.hpp).
#include "locus/kernels/mesh/coordinate_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "locus/core/format_significant.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

std::string sci(double v) { return format_significant(v, 3); }

}  // namespace

double bounding_box_diagonal(const double lo[3], const double hi[3]) {
  // Half the extents first: hi - lo of two finite doubles may overflow, their halves never do.
  double half[3], largest = 0;
  for (int k = 0; k < 3; ++k) {
    half[k] = std::max(0.0, 0.5 * hi[k] - 0.5 * lo[k]);
    largest = std::max(largest, half[k]);
  }
  if (!(largest > 0)) return 0.0;
  if (!std::isfinite(largest)) return std::numeric_limits<double>::infinity();
  const double sc = power_of_two_scale(largest);  // exact: no under/overflow in the squares
  double sum = 0;
  for (double h : half) sum += (h * sc) * (h * sc);
  return 2.0 * std::sqrt(sum) / sc;  // +inf when the diagonal exceeds the largest double
}

double bounding_box_diagonal(const Mesh& m) {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[0], -lo[0]};
  bool any = false;
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double p[3] = {m.x[v], m.y[v], m.z[v]};
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    any = true;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  return any ? bounding_box_diagonal(lo, hi) : 0.0;
}

void check_mesh_size(const Mesh& m, double diagonal) {
  if (diagonal == 0.0) return;
  const std::string range = "; scale it so that its size lies between " + sci(kMinMeshSize) + " and " +
                            sci(kMaxMeshSize) + " (the results scale with it)";
  if (diagonal > kMaxMeshSize)
    fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh is too large for double precision: its bounding-box diagonal is " +
                                  (std::isfinite(diagonal) ? sci(diagonal) : std::string("beyond 1.8e+308")) +
                                  ": its areas and squared lengths overflow double precision at that size" + range);
  if (diagonal < kMinMeshSize)
    fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh is too small for double precision: its bounding-box diagonal is " +
                                  sci(diagonal) + ": its areas and squared lengths underflow double precision at that size" + range);
}

}  // namespace locus
