// Tests for pipelines/anderson_acceleration. Oracle: the fixed point of an affine
// contraction x = M x + q, solved densely by Eigen. On an affine map Anderson
// acceleration with depth >= n is a Krylov method and reaches the fixed point in
// about n + 1 steps, while the plain iteration only contracts by ||M|| per step.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "locus/kernels/optim/anderson_acceleration.hpp"

using namespace locus;

namespace {

// Runs `steps` steps of x <- x + g(x), g(x) = M x + q - x, and returns the error to x*.
double run(int depth, int steps, const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& xs) {
  const size_t n = static_cast<size_t>(q.size());
  AndersonAcceleration aa(depth, n);
  std::vector<double> x(n, 0.0), g(n), out;
  for (int k = 0; k < steps; ++k) {
    const Eigen::Map<const Eigen::VectorXd> xv(x.data(), static_cast<Eigen::Index>(n));
    const Eigen::VectorXd gv = M * xv + q - xv;
    for (size_t i = 0; i < n; ++i) g[i] = gv[static_cast<Eigen::Index>(i)];
    aa.step(x, g, out);
    x = out;
  }
  double err = 0;
  for (size_t i = 0; i < n; ++i) err = std::max(err, std::abs(x[i] - xs[static_cast<Eigen::Index>(i)]));
  return err;
}

}  // namespace

TEST_CASE("Anderson acceleration solves an affine fixed point in n + 1 steps") {
  const int n = 5;
  Eigen::MatrixXd M(n, n);
  Eigen::VectorXd q(n);
  for (int i = 0; i < n; ++i) {
    q[i] = std::sin(1.0 + i);
    for (int j = 0; j < n; ++j) M(i, j) = 0.1 * std::cos(1.3 * i + 0.7 * j * j) / n;
  }
  M.diagonal().array() += 0.85;  // eigenvalues in [0.75, 0.95]: plain iteration converges slowly
  const Eigen::VectorXd xs = (Eigen::MatrixXd::Identity(n, n) - M).fullPivLu().solve(q);
  const double plain = run(0, n + 2, M, q, xs);
  const double accel = run(n, n + 2, M, q, xs);
  CHECK(plain > 1e-2);
  CHECK(accel < 1e-8);
  // A shallow history still helps.
  CHECK(run(2, 30, M, q, xs) < 0.1 * run(0, 30, M, q, xs));
}
