// Intrinsic mollification (Sharp & Crane, "A Laplacian for Nonmanifold Triangle
// Meshes", SGP 2020, §4.5): one epsilon added to every edge length so that each
// triangle satisfies the strict triangle inequality with margin delta. Adding a
// constant to all three sides raises every margin a + b - c by exactly epsilon,
// so the smallest sufficient epsilon is the worst shortfall.
#include "locus/kernels/mesh/intrinsic_mollification.hpp"

#include <algorithm>

namespace locus {

double mollify_intrinsic(IntrinsicTriangulation& T, double relative) {
  const size_t ns = T.length.size();
  if (ns == 0) return 0.0;
  double sum = 0.0;
  for (const double l : T.length) sum += l;
  const double delta = relative * sum / static_cast<double>(ns);
  double eps = 0.0;
  for (size_t f = 0; f < ns / 3; ++f) {
    const double* l = T.length.data() + 3 * f;
    for (int k = 0; k < 3; ++k) eps = std::max(eps, delta - (l[k] + l[(k + 1) % 3] - l[(k + 2) % 3]));
  }
  if (eps > 0.0)
    for (double& l : T.length) l += eps;
  return eps;
}

}  // namespace locus
