// The heat method's operators on the robust Laplacian's intrinsic triangles
// (kernels/include/locus/kernels/mesh/robust_heat_operators.hpp; thesis eqs.
// 6.3, 6.4, 6.6 with lengths instead of positions).
#include "locus/kernels/mesh/robust_heat_operators.hpp"

#include <cmath>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

// a * M + b * L on L's pattern (M is diagonal).
CscMatrix combine(const RobustOperators& R, double a, double b) {
  CscMatrix A = R.L;
  for (double& v : A.values) v *= b;
  for (int32_t j = 0; j < A.ncols; ++j) A.values[A.colptr[j]] += a * R.mass[j];
  return A;
}

}  // namespace

CscMatrix robust_heat_operator(const RobustOperators& R, double t) {
  if (!(t >= 0.0) || !std::isfinite(t))
    fail(ErrorCode::BadUsage, "robust_heat_operator: t must be finite and >= 0 (got " + std::to_string(t) + ")");
  return combine(R, 1.0, -t);
}

CscMatrix robust_regularized_laplacian(const RobustOperators& R, double rel) {
  if (!(rel > 0.0) || !std::isfinite(rel))
    fail(ErrorCode::BadUsage, "robust_regularized_laplacian: rel must be finite and > 0 (got " + std::to_string(rel) + ")");
  double trace_l = 0.0, trace_m = 0.0;
  for (int32_t j = 0; j < R.L.ncols; ++j) {
    trace_l -= R.L.values[R.L.colptr[j]];
    trace_m += R.mass[j];
  }
  if (!(trace_m > 0.0)) fail(ErrorCode::BadInput, "the mesh has no area; cannot regularize its Laplacian");
  return combine(R, rel * trace_l / trace_m, -1.0);
}

TriangleGradients intrinsic_triangle_gradients(const IntrinsicTriangulation& T, double area_scale) {
  TriangleGradients g;
  g.nv = T.num_vertices;
  g.nf = T.num_faces();
  const size_t nf = static_cast<size_t>(g.nf);
  g.tri.assign(T.vertex.begin(), T.vertex.end());
  g.area.resize(nf);
  g.basis.assign(9 * nf, 0.0);
  for (int32_t k = 0; k < g.nf; ++k) {
    cancel_point(k);
    const double* l = T.length.data() + 3 * static_cast<int64_t>(k);  // l[s]: side corner s -> corner s+1
    const double area = intrinsic_triangle_area(l[0], l[1], l[2]);
    if (!(area > 0.0) || !std::isfinite(area)) {
      g.area[k] = 0.0;
      continue;
    }
    const double px[3] = {0.0, l[0], (l[0] * l[0] + l[2] * l[2] - l[1] * l[1]) / (2.0 * l[0])};
    const double py[3] = {0.0, 0.0, 2.0 * area / l[0]};
    const double inv = 1.0 / (2.0 * area);
    double* b = g.basis.data() + 9 * static_cast<int64_t>(k);
    for (int s = 0; s < 3; ++s) {  // grad(phi_s) = z x (p_{s+2} - p_{s+1}) / (2A), the side opposite s turned
      const int a = (s + 1) % 3, c = (s + 2) % 3;
      b[3 * s + 0] = -(py[c] - py[a]) * inv;
      b[3 * s + 1] = (px[c] - px[a]) * inv;
    }
    g.area[k] = area_scale * area;
  }
  index_vertex_faces(g);
  return g;
}

}  // namespace locus
