// Anderson acceleration (type II, Walker & Ni 2011) of a fixed-point iteration
// x <- x + g(x), used by Algorithm 1 (pipelines/perfect_laplacian) on the log
// weights of the edges that are still active (pipelines/weight_active_set).
//
// It keeps the last `depth` differences ΔX, ΔG of the iterates and residuals and
// returns x_next = x + g - (ΔX + ΔG) γ with γ = argmin ||g - ΔG γ|| (the small
// normal equations, Tikhonov-regularized by 1e-10 · trace). depth 0 is the plain
// iteration. The vector length is fixed for the lifetime of an object: when the
// set of iterated unknowns changes, the caller starts a new one (the history of
// other unknowns says nothing about the new problem).
#pragma once
#include <cstddef>
#include <span>
#include <vector>

namespace locus {

class AndersonAcceleration {
 public:
  AndersonAcceleration(int depth, size_t n);
  size_t size() const { return n_; }
  void clear();
  // x, g: the current iterate and its residual g(x); out: the next iterate (size n).
  void step(std::span<const double> x, std::span<const double> g, std::vector<double>& out);

 private:
  int depth_;
  size_t n_;
  std::vector<std::vector<double>> dX_, dG_;  // oldest first
  std::vector<double> last_x_, last_g_;
  bool have_last_ = false;
};

}  // namespace locus
