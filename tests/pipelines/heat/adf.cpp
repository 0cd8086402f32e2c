// Tests for pipelines/adf (thesis §4.6, eq. 6.3): the auto-diffusion function
// (A_t^{-1})_ii and the heat kernel signature over several t.
// Oracles: the diagonal of a dense Eigen inverse of heat_operator(m, t) (built
// and inverted independently of locus's factor); locus full solves with e_i
// (the slow reference the subset path must match to 1e-10); selected inversion
// (kernels/selected_inversion) against the subset walk; and analytic facts:
// d/dt (A_t^{-1})_ii = h^T L_C h < 0 (strictly decreasing in t), ADF -> 1/M_ii as
// t -> 0, ADF -> 1/area as t -> infinity on a closed connected mesh.
#include "locus/pipelines/heat/adf.hpp"

#include <Eigen/Dense>
#include <doctest/doctest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"

using namespace locus;

namespace {

Eigen::MatrixXd dense_of(const CscMatrix& A) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(A.nrows, A.ncols);
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      D(A.rowind[p], j) = A.values[p];
      D(j, A.rowind[p]) = A.values[p];
    }
  return D;
}

double max_rel(const std::vector<double>& a, const std::vector<double>& ref) {
  double worst = 0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - ref[k]) / std::abs(ref[k]));
  return worst;
}

struct Case {
  const char* name;
  Mesh mesh;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({"icosphere", make_icosphere(3)});  // 642 vertices
  c.push_back({"torus", make_torus(36, 18)});     // 648 vertices
  return c;
}

}  // namespace

TEST_CASE("adf: subset walk equals full solves and a dense inverse, all vertices, several t") {
  for (const Case& c : cases()) {
    CAPTURE(c.name);
    const double h = mean_edge_length(c.mesh);
    const std::vector<double> ts{h * h, 30 * h * h, 500 * h * h};
    const HeatFactors H = factor_heat_operators(c.mesh, ts);
    const int32_t n = c.mesh.num_vertices();
    std::vector<double> sub(static_cast<size_t>(n) * ts.size()), full(sub.size()), sel(sub.size());
    heat_kernel_signature(H, {}, AdfMethod::Subset, sub);
    heat_kernel_signature(H, {}, AdfMethod::Full, full);
    heat_kernel_signature(H, {}, AdfMethod::Selinv, sel);
    CHECK(max_rel(sub, full) <= 1e-10);
    CHECK(max_rel(sel, sub) <= 1e-10);
    for (size_t j = 0; j < ts.size(); ++j) {
      const Eigen::MatrixXd Ainv = dense_of(heat_operator(c.mesh, ts[j])).inverse();
      double worst = 0;
      for (int32_t i = 0; i < n; ++i)
        worst = std::max(worst, std::abs(sub[i * ts.size() + j] - Ainv(i, i)) / Ainv(i, i));
      CHECK(worst <= 1e-10);
    }
  }
}

TEST_CASE("adf: chosen vertices, one factor, match the all-vertex run and the other methods") {
  const Mesh m = make_torus(36, 18);
  const double h = mean_edge_length(m);
  const double t = 10 * h * h;
  const HeatFactors H = factor_heat_operators(m, std::vector<double>{t});
  std::vector<double> all(m.num_vertices());
  auto_diffusion(H.factors[0], {}, AdfMethod::Subset, all);
  const std::vector<int32_t> pick{5, 0, 647, 300, 5};
  std::vector<double> some(pick.size()), some_full(pick.size()), some_sel(pick.size());
  auto_diffusion(H.factors[0], pick, AdfMethod::Subset, some);
  auto_diffusion(H.factors[0], pick, AdfMethod::Full, some_full);
  auto_diffusion(H.factors[0], pick, AdfMethod::Selinv, some_sel);
  for (size_t k = 0; k < pick.size(); ++k) {
    CHECK(some[k] == all[pick[k]]);  // same code path, same arithmetic
    CHECK(std::abs(some_full[k] - some[k]) <= 1e-10 * some[k]);
    CHECK(std::abs(some_sel[k] - some[k]) <= 1e-10 * some[k]);
  }
}

TEST_CASE("adf: heat kernel signature decreases strictly in t at every vertex") {
  // d/dt (A_t^{-1})_ii = -(A^{-1} dA/dt A^{-1})_ii = h^T L_C h with h = A_t^{-1} e_i:
  // negative since -L_C is PSD and its kernel (constants) does not contain h.
  const Mesh m = make_icosphere(3);
  const double h = mean_edge_length(m);
  const std::vector<double> ts{0.1 * h * h, h * h, 10 * h * h, 100 * h * h, 1000 * h * h};
  const HeatFactors H = factor_heat_operators(m, ts);
  std::vector<double> hks(static_cast<size_t>(m.num_vertices()) * ts.size());
  heat_kernel_signature(H, {}, AdfMethod::Subset, hks);
  int64_t violations = 0;
  for (int32_t i = 0; i < m.num_vertices(); ++i)
    for (size_t j = 1; j < ts.size(); ++j)
      if (!(hks[i * ts.size() + j] < hks[i * ts.size() + j - 1])) ++violations;
  CHECK(violations == 0);
}

TEST_CASE("adf: limits 1/M_ii for small t and 1/area for large t") {
  const Mesh m = make_icosphere(3);
  const auto mass = lumped_mass(m);
  double area = 0;
  for (double a : mass) area += a;
  const std::vector<double> ts{1e-9, 1e4};
  const HeatFactors H = factor_heat_operators(m, ts);
  std::vector<double> hks(static_cast<size_t>(m.num_vertices()) * 2);
  heat_kernel_signature(H, {}, AdfMethod::Subset, hks);
  double worst_small = 0, worst_large = 0;
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    worst_small = std::max(worst_small, std::abs(hks[2 * i] * mass[i] - 1.0));
    worst_large = std::max(worst_large, std::abs(hks[2 * i + 1] * area - 1.0));
  }
  // Small t: A^{-1} = M^{-1} + t M^{-1} L M^{-1} + O(t^2), relative deviation ~ t * |L_ii| / M_ii ~ 1e-5.
  CHECK(worst_small <= 1e-4);
  CHECK(worst_small > 0);
  // Large t on the unit sphere: the first nonzero eigenvalue of -L is 2, so the
  // deviation from 1/area is about 1/(1 + 2t) * (3/4pi) / (1/4pi) = 1.5e-4.
  CHECK(worst_large <= 1e-3);
}

TEST_CASE("adf: results do not depend on the thread count") {
  const Mesh m = make_torus(36, 18);
  const double h = mean_edge_length(m);
  const std::vector<double> ts{h * h, 50 * h * h};
  const HeatFactors H = factor_heat_operators(m, ts);
  std::vector<double> a(static_cast<size_t>(m.num_vertices()) * 2), b(a.size());
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    heat_kernel_signature(H, {}, AdfMethod::Subset, a);
  }
  heat_kernel_signature(H, {}, AdfMethod::Subset, b);
  CHECK(a == b);
}

TEST_CASE("adf: bad arguments are errors naming the problem") {
  const Mesh m = make_icosphere(1);
  CHECK_THROWS_AS(factor_heat_operators(m, std::vector<double>{0.0}), Error);
  CHECK_THROWS_AS(factor_heat_operators(m, std::vector<double>{}), Error);
  CHECK_THROWS_AS(factor_heat_operators(m, std::vector<double>{NAN}), Error);
  const HeatFactors H = factor_heat_operators(m, std::vector<double>{0.01});
  std::vector<double> out(1);
  const std::vector<int32_t> bad{m.num_vertices()};
  try {
    auto_diffusion(H.factors[0], bad, AdfMethod::Subset, out);
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadUsage);
    CHECK(std::string(e.what()).find("42") != std::string::npos);
  }
  std::vector<double> wrong(3);
  CHECK_THROWS_AS(auto_diffusion(H.factors[0], std::vector<int32_t>{0, 1}, AdfMethod::Subset, wrong), Error);
  CHECK_THROWS_AS(parse_adf_method("eigen"), Error);
}
