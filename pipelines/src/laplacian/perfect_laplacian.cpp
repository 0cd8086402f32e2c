// Perfect Laplacians for polygon meshes: Algorithm 1 (thesis §2.3, eqs. 2.4-2.11).
// See perfect_laplacian.hpp for the loop, the right-hand-side scale and the
// treatment of geometrically decaying weights. This file holds the iteration on
// a PerfectLaplacianProblem (the multiplicative method here, the Newton method
// in perfect_laplacian_newton.cpp); the problem of a mesh and the alignment of
// the result are in perfect_laplacian_mesh.cpp.
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/optim/anderson_acceleration.hpp"
#include "locus/pipelines/laplacian/perfect_laplacian_newton.hpp"
#include "locus/pipelines/laplacian/weight_active_set.hpp"

namespace locus {

namespace perfect_laplacian_detail {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double bbox_diagonal(int dims, const Coords& p, size_t n) {
  double d2 = 0;
  for (int k = 0; k < dims; ++k) {
    if (n == 0) break;
    const auto [lo, hi] = std::minmax_element(p[k].begin(), p[k].begin() + static_cast<std::ptrdiff_t>(n));
    d2 += (*hi - *lo) * (*hi - *lo);
  }
  return std::sqrt(d2);
}

bool scale_free(const PerfectLaplacianProblem& P) {
  for (int k = 0; k < P.dims; ++k)
    for (double x : P.b[k])
      if (x != 0.0) return false;
  return true;
}

double edge_length(int dims, const Coords& p, int32_t a, int32_t b) {
  double s = 0;
  for (int k = 0; k < dims; ++k) {
    const double d = p[k][b] - p[k][a];
    s += d * d;
  }
  return std::sqrt(s);
}

}  // namespace perfect_laplacian_detail

namespace {

using perfect_laplacian_detail::bbox_diagonal;
using perfect_laplacian_detail::edge_length;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }


// min_weight, min_positive_weight, zero_weights, at_floor from R.weights.
void weight_statistics(const PerfectLaplacianOptions& opt, PerfectLaplacianResult& R) {
  double wmax = 0;
  R.min_weight = R.weights.empty() ? 0.0 : R.weights[0];
  R.min_positive_weight = 0;
  for (double x_ : R.weights) {
    wmax = std::max(wmax, x_);
    R.min_weight = std::min(R.min_weight, x_);
    if (x_ > 0 && (R.min_positive_weight == 0 || x_ < R.min_positive_weight)) R.min_positive_weight = x_;
  }
  for (double x_ : R.weights) {
    if (x_ <= opt.zero_weight_rel * wmax) ++R.zero_weights;
    if (x_ == 0.0) ++R.at_floor;
  }
}

// Problem checks shared by both methods (BadUsage / BadInput naming the edge).
void validate_problem(const PerfectLaplacianProblem& P, const PerfectLaplacianOptions& opt) {
  const size_t ne = P.e0.size();
  if (P.dims != 2 && P.dims != 3) fail(ErrorCode::BadUsage, "perfect Laplacian: dims must be 2 or 3");
  if (P.e1.size() != ne || P.target_length.size() != ne)
    fail(ErrorCode::BadInput, "perfect Laplacian: one target length per edge expected");
  if (opt.max_iterations < 1 || !(opt.eps > 0.0))
    fail(ErrorCode::BadUsage, "perfect Laplacian: need max_iterations >= 1 and eps > 0");
  for (size_t e = 0; e < ne; ++e)
    if (!(P.target_length[e] > 0.0) || !std::isfinite(P.target_length[e]))
      fail(ErrorCode::BadInput, "perfect Laplacian: edge " + std::to_string(e) + " (" + std::to_string(P.e0[e]) +
                                    ", " + std::to_string(P.e1[e]) + ") has target length " +
                                    std::to_string(P.target_length[e]) + "; lengths must be positive");
  if (!P.initial_weights.empty() && P.initial_weights.size() != ne)
    fail(ErrorCode::BadInput, "perfect Laplacian: one initial weight per edge expected");
}

// ω^(0) = 1 (or the caller's) as log weights U.
std::vector<double> initial_log_weights(const PerfectLaplacianProblem& P) {
  const size_t ne = P.e0.size();
  std::vector<double> U(ne, 0.0);
  if (!P.initial_weights.empty())
    for (size_t e = 0; e < ne; ++e) {
      if (!(P.initial_weights[e] > 0.0) || !std::isfinite(P.initial_weights[e]))
        fail(ErrorCode::BadInput, "perfect Laplacian: initial weight of edge " + std::to_string(e) + " is not positive");
      U[e] = std::log(P.initial_weights[e]);
    }
  return U;
}

// One run of the multiplicative method (the thesis' loop, eq. 2.8, with the
// generalizations of the header). The state lives in members so that each step
// of an iteration (solve, residual, accelerated update, floor) is a method.
//
// The state is the vector U of log raw weights; the system is assembled with
// the normalized weights ω = exp(U - C), C = log ||exp U|| over the edges not
// dropped, and b scaled by exp(-C).
class MultiplicativeRun {
 public:
  MultiplicativeRun(const PerfectLaplacianProblem& P, const PerfectLaplacianOptions& opt, const RunContext& ctx,
                    PerfectLaplacianResult& R, Clock::time_point t_first)
      : P_(P), opt_(opt), ctx_(ctx), R_(R), t_first_(t_first), nv_(P.nv), ne_(P.e0.size()), dims_(P.dims),
        sys_(nv_, P.e0, P.e1, P.fixed, opt.system) {
    R_.order_s = sys_.order_s();
    R_.analyze_s = sys_.analyze_s();
    // With b = 0 the embedding does not change when all weights are scaled: the
    // steady state fixes ω only up to scale and the active edges' length ratios to
    // a common μ^-1 that need not be 1 (§2.3.3). The residual is then the log
    // ratio minus its ω²-weighted mean c (the first-order shift of the
    // normalization), so that it vanishes at the steady state instead of drifting
    // by log μ^-1 per iteration. With b != 0 the raw weights carry the scale (see
    // the header) and the residual is the plain log ratio.
    scale_free_ = perfect_laplacian_detail::scale_free(P_);
    R_.scale_free = scale_free_;
    U_ = initial_log_weights(P_);
    aset_.emplace(nv_, P_.e0, P_.e1, P_.fixed, opt_.active_set);
    w_.resize(ne_);
    lse_ref_ = aset_->active().empty() ? 0.0 : active_lse();
    weights_from();
    aa_ = std::make_unique<AndersonAcceleration>(opt_.anderson_depth, aset_->active().size());
    f_.resize(ne_);
    g_.resize(ne_);
  }

  void iterate();
  void finish();

 private:
  double max_active_u() const;
  void weights_from();
  double active_lse() const;
  void restart_acceleration();
  void record_time(int k, Clock::time_point t_iter);
  double solve_embedding(int k);
  void compute_residual();
  void accelerated_step();
  bool floor_backstop();

  const PerfectLaplacianProblem& P_;
  const PerfectLaplacianOptions& opt_;
  const RunContext& ctx_;
  PerfectLaplacianResult& R_;
  const Clock::time_point t_first_;  // the first iteration's time includes ordering and analysis
  const int32_t nv_;
  const size_t ne_;
  const int dims_;
  EmbeddingSystem sys_;
  bool scale_free_ = false;
  std::vector<double> U_;                // log raw weights
  std::optional<WeightActiveSet> aset_;  // built after U_ is checked
  std::vector<double> w_;                // normalized weights, dropped edges exactly 0
  double rhs_scale_ = 1.0;
  double lse_ref_ = 0;                   // log-sum-exp of the active U at the start
  std::unique_ptr<AndersonAcceleration> aa_;
  double best_f_ = std::numeric_limits<double>::infinity();
  std::vector<double> f_, g_, x_, r_, xn_;  // f, g per edge; x, r, xn per active edge
  Coords V_, Vprev_;
  bool have_prev_ = false;
  std::vector<double> later_s_;
};

double MultiplicativeRun::max_active_u() const {
  double umax = -std::numeric_limits<double>::infinity();
  for (int32_t e : aset_->active()) umax = std::max(umax, U_[e]);
  return umax;
}

// Normalized weights from U: dropped edges exactly 0.
void MultiplicativeRun::weights_from() {
  double umax = -std::numeric_limits<double>::infinity();
  for (size_t e = 0; e < ne_; ++e)
    if (aset_->state(e) != WeightState::dropped) umax = std::max(umax, U_[e]);
  double s = 0;
  for (size_t e = 0; e < ne_; ++e)
    if (aset_->state(e) != WeightState::dropped) s += std::exp(2 * (U_[e] - umax));
  const double c = umax + 0.5 * std::log(s);
  for (size_t e = 0; e < ne_; ++e) w_[e] = aset_->state(e) == WeightState::dropped ? 0.0 : std::exp(U_[e] - c);
  rhs_scale_ = std::exp(-c);
}

// In the scale-free case the level of the active U is arbitrary; it is kept at
// its initial log-sum-exp so that passive edges (not iterated) stay comparable.
double MultiplicativeRun::active_lse() const {
  const double umax = max_active_u();
  double s = 0;
  for (int32_t e : aset_->active()) s += std::exp(U_[e] - umax);
  return umax + std::log(s);
}

void MultiplicativeRun::restart_acceleration() {
  aa_ = std::make_unique<AndersonAcceleration>(opt_.anderson_depth, aset_->active().size());
  best_f_ = std::numeric_limits<double>::infinity();
}

void MultiplicativeRun::record_time(int k, Clock::time_point t_iter) {
  if (k == 1)
    R_.first_iter_s = seconds_since(t_first_);
  else
    later_s_.push_back(seconds_since(t_iter));
}

// Factor K(ω), solve for V; returns the largest vertex change of this
// iteration against the diagonal (0 in the first).
double MultiplicativeRun::solve_embedding(int k) {
  // Dropped weights are exact zeros; the positivity floor is needed only when
  // they leave some free vertex without a positive path to a fixed one.
  sys_.set_weight_floor_rel(aset_->anchored() ? 0.0 : opt_.system.weight_floor_rel);
  sys_.factor(w_, ctx_);
  sys_.solve(dims_, P_.fixed_pos, P_.b, rhs_scale_, V_);
  ++R_.factorizations;
  R_.iterations = k;

  const double diag = bbox_diagonal(dims_, V_, static_cast<size_t>(nv_));
  double change = 0;
  if (have_prev_)
    for (int32_t v = 0; v < nv_; ++v) {
      double s = 0;
      for (int c = 0; c < dims_; ++c) s += (V_[c][v] - Vprev_[c][v]) * (V_[c][v] - Vprev_[c][v]);
      change = std::max(change, s);
    }
  change = std::sqrt(change);
  const double change_rel = diag > 0 ? change / diag : 0.0;
  if (have_prev_) R_.change_history.push_back(change_rel);
  R_.last_change_rel = have_prev_ ? change_rel : 0.0;
  return change_rel;
}

// The plain step of eq. 2.8 in log form is U += f, f = log(||e|| / ||ê||); g is
// the residual (f minus the normalization shift in the scale-free case).
void MultiplicativeRun::compute_residual() {
  double c = 0, cw = 0;
  for (size_t e = 0; e < ne_; ++e) {
    double len = edge_length(dims_, V_, P_.e0[e], P_.e1[e]);
    if (!(len > 0.0)) len = 1e-300;  // collapsed edge: its weight shrinks as fast as allowed
    f_[e] = std::log(len / P_.target_length[e]);
  }
  if (scale_free_ && opt_.center_residual) {
    for (int32_t e : aset_->active()) {
      c += w_[e] * w_[e] * f_[e];
      cw += w_[e] * w_[e];
    }
    c = cw > 0 ? c / cw : 0.0;
  }
  for (size_t e = 0; e < ne_; ++e) g_[e] = f_[e] - c;
}

// U of the active edges: pushed edges by their push, the others by the
// Anderson-accelerated step of U <- U + relaxation · g, safeguarded.
void MultiplicativeRun::accelerated_step() {
  const auto& A = aset_->active();
  const size_t na = A.size();
  x_.resize(na);
  r_.resize(na);
  double fnorm = 0;
  for (size_t i = 0; i < na; ++i) {
    x_[i] = U_[A[i]];
    r_[i] = aset_->pushed(A[i]) ? 0.0 : opt_.relaxation * g_[A[i]];  // converged as far as the acceleration is concerned
    fnorm += r_[i] * r_[i];
  }
  fnorm = std::sqrt(fnorm);
  if (opt_.anderson_depth > 0 && fnorm > opt_.anderson_restart * best_f_) aa_->clear();  // extrapolation made it worse
  best_f_ = std::min(best_f_, fnorm);
  aa_->step(x_, r_, xn_);
  // Safeguard: no weight changes by more than a factor exp(max_log_step) at once.
  double big = 0;
  for (size_t i = 0; i < na; ++i) big = std::max(big, std::abs(xn_[i] - x_[i]));
  const double t = big > opt_.max_log_step ? opt_.max_log_step / big : 1.0;
  for (size_t i = 0; i < na; ++i)
    U_[A[i]] = aset_->pushed(A[i]) ? x_[i] + aset_->push_step(A[i], g_[A[i]]) : x_[i] + t * (xn_[i] - x_[i]);
  if (scale_free_ && na > 0) {
    const double shift = active_lse() - lse_ref_;
    for (int32_t e : A) U_[e] -= shift;
  }
}

// Backstop: a weight below floor_rel · max has reached its limit 0 whatever its
// history; one that may not be dropped any more is held at the floor. Returns
// whether an edge was dropped.
bool MultiplicativeRun::floor_backstop() {
  const double log_floor = std::log(opt_.floor_rel);
  const double umax = max_active_u();
  bool dropped = false;
  const std::vector<int32_t> Acopy = aset_->active();  // drop() rebuilds the active list
  for (int32_t e : Acopy)
    if (U_[e] - umax <= log_floor) {
      if (opt_.drop_decaying && aset_->drop(static_cast<size_t>(e)))
        dropped = true;
      else
        U_[e] = umax + log_floor;
    }
  return dropped;
}

void MultiplicativeRun::iterate() {
  for (int k = 1; k <= opt_.max_iterations; ++k) {
    ctx_.check_cancel();
    const auto t_iter = Clock::now();
    const double change_rel = solve_embedding(k);
    compute_residual();

    const bool converged_now = have_prev_ && change_rel < opt_.eps;
    if (converged_now && opt_.drop_decaying && R_.kkt_rounds < opt_.max_kkt_rounds &&
        aset_->revive_violators(g_, U_) > 0) {
      // Steady state reached with this active set, but some dropped edges would
      // grow back (KKT): they return at their pre-decay weight; iterate on.
      ++R_.kkt_rounds;
      restart_acceleration();
      weights_from();
      Vprev_.swap(V_);
      record_time(k, t_iter);
      continue;
    }
    if (converged_now || k == opt_.max_iterations) {
      R_.converged = converged_now;
      record_time(k, t_iter);
      break;  // keep ω^(k): V is the equilibrium of exactly these weights
    }

    // Established decays are pushed, vanished ones dropped (weight_active_set.hpp).
    if (opt_.drop_decaying && aset_->observe(g_, w_, U_) > 0) restart_acceleration();
    accelerated_step();
    if (floor_backstop()) restart_acceleration();
    weights_from();
    Vprev_.swap(V_);
    have_prev_ = true;
    record_time(k, t_iter);
    ctx_.report(static_cast<double>(k) / opt_.max_iterations, "perfect Laplacian iterations");
  }
}

void MultiplicativeRun::finish() {
  // The weights V is in equilibrium with (ω of the last solve).
  R_.pos = std::move(V_);
  R_.weights = std::move(w_);
  R_.rhs_scale = rhs_scale_;
  R_.iter_s = perfect_laplacian_detail::median(later_s_);
  R_.revived = aset_->num_revived();
  R_.kkt_violation = aset_->num_dropped() > 0 ? aset_->max_violation(g_) : 0.0;
}

}  // namespace

PerfectLaplacianResult run_perfect_laplacian(const PerfectLaplacianProblem& P, const PerfectLaplacianOptions& opt,
                                             const RunContext& ctx) {
  validate_problem(P, opt);
  if (opt.method == PerfectLaplacianMethod::newton) {
    PerfectLaplacianResult N = run_perfect_laplacian_newton(P, opt, ctx);
    weight_statistics(opt, N);
    return N;
  }
  PerfectLaplacianResult R;
  const auto t_first = Clock::now();
  MultiplicativeRun run(P, opt, ctx, R, t_first);
  run.iterate();
  run.finish();
  weight_statistics(opt, R);
  return R;
}

}  // namespace locus
