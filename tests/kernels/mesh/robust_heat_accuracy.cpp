// Accuracy of the heat method (thesis §6.5; Crane et al. 2013) run on the robust
// Laplacian's intrinsic triangles (kernels/src/mesh/robust_laplacian.cpp) on a
// unit icosphere with planted defects (mesh_defects_plant.hpp), against the exact
// oracle, the great-circle distance acos(p . p0). The heat method is written out
// here with Eigen (u = (M - tL)^-1 delta, X = -grad u / |grad u| per intrinsic
// triangle laid out in the plane from its lengths, L phi = div X) so that it
// depends on nothing but the operator under test. Target: the mean error at the
// original vertices within 1.5x the clean mesh's.
#include <doctest/doctest.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_defects_plant.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/robust_laplacian.hpp"

using namespace locus;

namespace {

using SpMat = Eigen::SparseMatrix<double>;

// a * M - b * L as a full symmetric Eigen matrix; rows of `identity` get 1 on the
// diagonal and nothing else.
SpMat combine(const RobustOperators& R, double a, double b, const std::vector<char>& identity) {
  std::vector<Eigen::Triplet<double>> t;
  const CscMatrix& L = R.L;
  for (int32_t j = 0; j < L.ncols; ++j)
    for (int64_t p = L.colptr[j]; p < L.colptr[j + 1]; ++p) {
      const int32_t i = L.rowind[p];
      if (identity[i] || identity[j]) continue;
      const double v = -b * L.values[p] + (i == j ? a * R.mass[j] : 0.0);
      t.emplace_back(i, j, v);
      if (i != j) t.emplace_back(j, i, v);
    }
  for (int32_t v = 0; v < L.ncols; ++v)
    if (identity[v]) t.emplace_back(v, v, 1.0);
  SpMat A(L.nrows, L.ncols);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// Heat distance from `source` on the intrinsic triangulation; NaN at isolated vertices.
std::vector<double> heat_distance(const Mesh& m, int32_t source) {
  const RobustOperators R = robust_laplacian(m);
  const IntrinsicTriangulation& T = R.triangulation;
  const int32_t n = m.num_vertices();
  std::vector<char> isolated(static_cast<size_t>(n), 1);
  for (const int32_t v : T.vertex) isolated[v] = 0;
  const double h = mean_edge_length(m);
  Eigen::SimplicialLDLT<SpMat> heat(combine(R, 1.0, h * h, isolated));
  REQUIRE(heat.info() == Eigen::Success);
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
  delta[source] = 1.0;
  const Eigen::VectorXd u = heat.solve(delta);
  // Per intrinsic triangle: corners p0 = (0, 0), p1 = (l0, 0), p2 above.
  Eigen::VectorXd div = Eigen::VectorXd::Zero(n);
  for (int32_t f = 0; f < T.num_faces(); ++f) {
    const int32_t* v = T.vertex.data() + 3 * f;
    const double* l = T.length.data() + 3 * f;  // l[k]: side v[k] -> v[k+1]
    const double area = intrinsic_triangle_area(l[0], l[1], l[2]);
    const double px[3] = {0.0, l[0], (l[0] * l[0] + l[2] * l[2] - l[1] * l[1]) / (2 * l[0])};
    const double py[3] = {0.0, 0.0, 2 * area / l[0]};
    double gx = 0, gy = 0;
    for (int k = 0; k < 3; ++k) {  // grad u = sum u_k J e_k / 2A, e_k the side opposite k (ccw)
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      gx += u[v[k]] * -(py[b] - py[a]);
      gy += u[v[k]] * (px[b] - px[a]);
    }
    const double g = std::hypot(gx, gy);
    if (!(g > 0)) continue;
    const double X[2] = {-gx / g, -gy / g};
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      // cot at a (opposite side b -> k, length l[b]) and at b (opposite k -> a, l[k]).
      const double cot_a = intrinsic_cotan(l[k], l[a], l[b], area);
      const double cot_b = intrinsic_cotan(l[a], l[b], l[k], area);
      const double ekb = (px[b] - px[k]) * X[0] + (py[b] - py[k]) * X[1];
      const double eka = (px[a] - px[k]) * X[0] + (py[a] - py[k]) * X[1];
      div[v[k]] += 0.25 * (cot_a * ekb + cot_b * eka);  // halved for the two sheets
    }
  }
  std::vector<char> pinned = isolated;
  pinned[source] = 1;
  Eigen::SimplicialLDLT<SpMat> poisson(combine(R, 0.0, 1.0, pinned));
  REQUIRE(poisson.info() == Eigen::Success);
  Eigen::VectorXd rhs = -div;
  for (int32_t v = 0; v < n; ++v)
    if (pinned[v]) rhs[v] = 0.0;
  const Eigen::VectorXd phi = poisson.solve(rhs);
  double lo = INFINITY;
  for (int32_t v = 0; v < n; ++v)
    if (!isolated[v]) lo = std::min(lo, phi[v]);
  std::vector<double> d(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) d[v] = isolated[v] ? NAN : phi[v] - lo;
  return d;
}

// Mean |d - great circle| over the first nv0 vertices (the icosphere's own).
double mean_error(const Mesh& m, const std::vector<double>& d, int32_t nv0, int32_t source) {
  double sum = 0.0;
  for (int32_t v = 0; v < nv0; ++v) {
    const double c = m.x[v] * m.x[source] + m.y[v] * m.y[source] + m.z[v] * m.z[source];
    sum += std::abs(d[v] - std::acos(std::clamp(c, -1.0, 1.0)));
  }
  return sum / nv0;
}

}  // namespace

TEST_CASE("robust Laplacian: heat distance on an icosphere with planted defects stays within 1.5x the clean error") {
  const int level = 5, sites = 8;
  const Mesh clean = make_icosphere(level);
  const int32_t nv0 = clean.num_vertices();
  const double clean_error = mean_error(clean, heat_distance(clean, 0), nv0, 0);
  MESSAGE("icosphere " << level << " clean: mean error " << clean_error);
  CHECK(clean_error < 0.01);
  for (int k = 0; k < kNumPlantedDefects; ++k) {
    const PlantedDefect kind = static_cast<PlantedDefect>(k);
    const Mesh m = plant_mesh_defect(clean, kind, sites);
    const double e = mean_error(m, heat_distance(m, 0), nv0, 0);
    MESSAGE(std::string(planted_defect_name(kind)) << " x" << sites << ": mean error " << e << " (" << e / clean_error
                                      << "x clean)");
    CAPTURE(planted_defect_name(kind));
    CHECK(e <= 1.5 * clean_error);
  }
}
