// Anderson acceleration of a fixed-point iteration; see anderson_acceleration.hpp.
#include "locus/kernels/optim/anderson_acceleration.hpp"

#include <utility>

namespace locus {

AndersonAcceleration::AndersonAcceleration(int depth, size_t n) : depth_(depth < 0 ? 0 : depth), n_(n) {}

void AndersonAcceleration::clear() {
  dX_.clear();
  dG_.clear();
  have_last_ = false;
}

void AndersonAcceleration::step(std::span<const double> x, std::span<const double> g, std::vector<double>& out) {
  const size_t n = n_;
  if (depth_ > 0 && have_last_) {
    std::vector<double> dx(n), dg(n);
    for (size_t i = 0; i < n; ++i) {
      dx[i] = x[i] - last_x_[i];
      dg[i] = g[i] - last_g_[i];
    }
    dX_.push_back(std::move(dx));
    dG_.push_back(std::move(dg));
    if (static_cast<int>(dX_.size()) > depth_) {
      dX_.erase(dX_.begin());
      dG_.erase(dG_.begin());
    }
  }
  if (depth_ > 0) {
    last_x_.assign(x.begin(), x.end());
    last_g_.assign(g.begin(), g.end());
    have_last_ = true;
  }
  out.resize(n);
  for (size_t i = 0; i < n; ++i) out[i] = x[i] + g[i];
  const int m = static_cast<int>(dG_.size());
  if (m == 0) return;
  // Normal equations (ΔG^T ΔG + λ I) γ = ΔG^T g, symmetric positive definite.
  std::vector<double> G(static_cast<size_t>(m * m)), r(static_cast<size_t>(m));
  double trace = 0;
  for (int a = 0; a < m; ++a) {
    for (int b = 0; b <= a; ++b) {
      double s = 0;
      for (size_t i = 0; i < n; ++i) s += dG_[a][i] * dG_[b][i];
      G[a * m + b] = G[b * m + a] = s;
    }
    trace += G[a * m + a];
    double s = 0;
    for (size_t i = 0; i < n; ++i) s += dG_[a][i] * g[i];
    r[a] = s;
  }
  if (!(trace > 0)) return;
  for (int a = 0; a < m; ++a) G[a * m + a] += 1e-10 * trace;
  for (int c = 0; c < m; ++c) {  // Gaussian elimination; SPD needs no pivoting
    for (int a = c + 1; a < m; ++a) {
      const double l = G[a * m + c] / G[c * m + c];
      for (int b = c; b < m; ++b) G[a * m + b] -= l * G[c * m + b];
      r[a] -= l * r[c];
    }
  }
  std::vector<double> gamma(static_cast<size_t>(m));
  for (int a = m - 1; a >= 0; --a) {
    double s = r[a];
    for (int b = a + 1; b < m; ++b) s -= G[a * m + b] * gamma[b];
    gamma[a] = s / G[a * m + a];
  }
  for (int a = 0; a < m; ++a)
    for (size_t i = 0; i < n; ++i) out[i] -= gamma[a] * (dX_[a][i] + dG_[a][i]);
}

}  // namespace locus
