// Cholesky core on mesh operators: heat operators M - tL_C at
// t = h^2 and the regularized Laplacian -L_C + eps M on icosphere, random
// sphere, torus and disk meshes factor and solve to 1e-10 relative residual;
// nnz(L) and solutions match Eigen's SimplicialLLT under the same permutation;
// the Laplacian's regularization does not depend on the mesh's units.
#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/mesh_io.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

double solve_residual(const CscMatrix& A, const NumericFactor& F, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> b(A.ncols), x, Ax(A.ncols);
  for (auto& v : b) v = u(rng);
  x = b;
  solve(F, x);
  symmetric_multiply(A, x.data(), Ax.data());
  double r = 0, nb = 0;
  for (int32_t i = 0; i < A.ncols; ++i) { r += (Ax[i] - b[i]) * (Ax[i] - b[i]); nb += b[i] * b[i]; }
  return std::sqrt(r / nb);
}

void check_operator(const CscMatrix& A, bool compare_eigen) {
  auto S = analyze(A, order_matrix(A));
  const NumericFactor F = factorize(S, A);
  CHECK(solve_residual(A, F, 17) <= 1e-10);
  if (!compare_eigen) return;
  const int32_t n = A.ncols;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(n);
  for (int32_t k = 0; k < n; ++k) P.indices()[S->perm[k]] = k;
  const Eigen::SparseMatrix<double> E = test::to_eigen(A);
  const Eigen::SparseMatrix<double> PE = (P * E * P.transpose()).eval();
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(PE);
  REQUIRE(llt.info() == Eigen::Success);
  CHECK(Eigen::SparseMatrix<double>(llt.matrixL()).nonZeros() == S->nnz_exact);
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
  const Eigen::VectorXd xe = P.transpose() * llt.solve(P * b);
  std::vector<double> x(b.data(), b.data() + n);
  solve(F, x);
  double dx = 0, nx = 0;
  for (int32_t i = 0; i < n; ++i) { dx = std::max(dx, std::abs(x[i] - xe[i])); nx = std::max(nx, std::abs(xe[i])); }
  CHECK(dx <= 1e-10 * nx);
}

}  // namespace

TEST_CASE("heat and regularized Laplacian operators of generated meshes factor and solve") {
  const Mesh meshes[] = {make_icosphere(4), make_random_sphere(3000, 7), make_torus(60, 30), make_disk(30)};
  for (const Mesh& m : meshes) {
    CAPTURE(m.num_vertices());
    const double h = mean_edge_length(m);
    check_operator(heat_operator(m, h * h), true);
    check_operator(regularized_laplacian(m), true);
  }
}

TEST_CASE("the Laplacian's regularization is relative to the mesh's scale") {
  Mesh m = make_icosphere(5);  // 10k vertices
  const std::string arm = std::string(LOCUS_MESH_CACHE_DIR) + "/armadillo.off";
  bool real = false;
  try {
    m = read_mesh(arm);
    real = true;
  } catch (const std::exception&) {
    MESSAGE("armadillo.off not found in the mesh cache; using an icosphere (run tools/fetch_meshes.sh)");
  }
  CAPTURE(real);
  // As given (armadillo: area ~4e4), scaled to unit area, and scaled up 1000x.
  double area = 0;
  for (double a : lumped_mass(m)) area += a;
  for (double factor : {1.0, 1.0 / std::sqrt(area), 1000.0}) {
    Mesh s = m;
    for (auto* c : {&s.x, &s.y, &s.z})
      for (double& v : *c) v *= factor;
    const CscMatrix A = regularized_laplacian(s);
    const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
    CAPTURE(factor);
    CHECK(solve_residual(A, F, 5) <= 1e-10);
  }
}
