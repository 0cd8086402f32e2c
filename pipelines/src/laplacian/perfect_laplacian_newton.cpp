// Projected Newton method for the steady state of Algorithm 1 (thesis §2.3.3,
// eq. 2.11); see perfect_laplacian_newton.hpp for the objective, the Hessian
// product and why.
#include "locus/pipelines/laplacian/perfect_laplacian_newton.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/pipelines/laplacian/weight_active_set.hpp"

namespace locus {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// One CG step's update: x += alpha p, r -= alpha Ap, zr = M^-1 r; returns
// r · zr. The arrays are distinct; saying so (restrict) lets the compiler
// vectorize the loop as it did before the run was split into methods, and the
// vectorized reduction (products not fused into the sum) is part of the results.
double cg_update(size_t n, double alpha, const double* __restrict p, const double* __restrict Ap,
                 const double* __restrict Minv, double* __restrict x, double* __restrict r, double* __restrict zr) {
  double rz_new = 0;
  for (size_t i = 0; i < n; ++i) {
    x[i] += alpha * p[i];
    r[i] -= alpha * Ap[i];
    zr[i] = Minv[i] * r[i];
    rz_new += r[i] * zr[i];
  }
  return rz_new;
}

// The outcome of one line search (NewtonRun::line_search).
struct LineSearchStep {
  bool accepted = false;
  bool first_trial = false;  // the full Newton step (or at least half of it) was taken
  bool first_pass = false;   // along the Newton direction, not the gradient fallback
  double t = 0;              // the step length taken
  double E = 0, S = 0;       // E and S at the accepted weights
};

// One run of the interior-point Newton method. The state lives in members so
// that each step of an iteration (gradient, Newton direction, line search, dual
// step, acceptance) is a method of its own; the arithmetic is that of the
// header's description, step by step. Vectors indexed by i run over the
// iterated edges act_[i]; vectors indexed by e over all edges.
class NewtonRun {
 public:
  NewtonRun(const PerfectLaplacianProblem& P, const PerfectLaplacianOptions& opt, const RunContext& ctx,
            PerfectLaplacianResult& R)
      : P_(P), opt_(opt), ctx_(ctx), R_(R), nv_(P.nv), ne_(P.e0.size()), dims_(P.dims),
        sys_(nv_, P.e0, P.e1, P.fixed, opt.system) {
    R_.order_s = sys_.order_s();
    R_.analyze_s = sys_.analyze_s();
    scale_free_ = perfect_laplacian_detail::scale_free(P_);
    R_.scale_free = scale_free_;
    select_iterated_edges();
    set_initial_weights();
    for (int k = 0; k < dims_; ++k) zero_pos_[k].assign(static_cast<size_t>(nv_), 0.0);
    evaluate(om_, V_, l2_, E_, S_);
    rescale(0.0);
    for (auto* v : {&g_, &Minv_, &bar_, &x_, &r_, &zr_, &p_, &Ap_, &d_}) v->resize(na_);
    lam_.assign(na_, -1.0);
    wt_.resize(ne_);
    for (int k = 0; k < dims_; ++k) y_[k].assign(static_cast<size_t>(nv_), 0.0);
  }

  void iterate(Clock::time_point t_first);
  void finish();

 private:
  void select_iterated_edges();
  void set_initial_weights();
  double evaluate(const std::vector<double>& w, Coords& X, std::vector<double>& l2, double& e_out, double& s_out);
  double log_barrier(const std::vector<double>& w) const;
  void rescale(double tau);
  void hessian_product(const std::vector<double>& pv, std::vector<double>& out);
  double barrier_and_gradient(double mu, double& tau);
  void newton_direction(double eta, int cg_max);
  LineSearchStep line_search(double tau);
  void dual_step(double tau, bool newton_dir);
  double accept_step(const LineSearchStep& step, double tau);
  void zero_vanished_weights();
  void normalize_iterated_mean();
  double steady_state_violation() const;

  const PerfectLaplacianProblem& P_;
  const PerfectLaplacianOptions& opt_;
  const RunContext& ctx_;
  PerfectLaplacianResult& R_;
  const int32_t nv_;
  const size_t ne_;
  const int dims_;
  EmbeddingSystem sys_;
  bool scale_free_ = false;
  std::vector<int32_t> act_;  // iterated edges: those with a free end
  size_t na_ = 0;
  std::vector<double> c_;     // ||ê_e||²
  std::vector<double> om_;    // raw weights ω
  std::vector<int32_t> uf_;   // union-find scratch of edges_anchor_free_vertices
  Coords zero_pos_;
  double E_ = 0, S_ = 0;
  // b = 0: the factor in sys_ is K(ω / fscale_), so K^-1 scales by 1 / fscale_.
  double fscale_ = 1.0;
  Coords V_, Vt_;
  std::vector<double> l2_, l2t_;
  // Per iterated edge: multiplier, gradient, preconditioner, barrier curvature,
  // CG vectors, search direction; wt_ the trial weights (per edge).
  std::vector<double> lam_, g_, Minv_, bar_, x_, r_, zr_, p_, Ap_, d_, wt_;
  Coords y_, z_;
  std::vector<double> later_s_;
};

// Iterated edges: those with a free end (both ends fixed: no row of eq. 2.4).
void NewtonRun::select_iterated_edges() {
  for (size_t e = 0; e < ne_; ++e)
    if (!(P_.fixed[P_.e0[e]] && P_.fixed[P_.e1[e]])) act_.push_back(static_cast<int32_t>(e));
  na_ = act_.size();
  c_.resize(ne_);
  for (size_t e = 0; e < ne_; ++e) c_[e] = P_.target_length[e] * P_.target_length[e];
}

// Algorithm 1 starts at ω = 1, or at the caller's positive weights.
void NewtonRun::set_initial_weights() {
  om_.assign(ne_, 1.0);
  if (P_.initial_weights.empty()) return;
  om_ = P_.initial_weights;
  for (size_t e = 0; e < ne_; ++e)
    if (!(om_[e] > 0.0) || !std::isfinite(om_[e]))
      fail(ErrorCode::BadInput, "perfect Laplacian: initial weight of edge " + std::to_string(e) + " (" +
                                    std::to_string(P_.e0[e]) + ", " + std::to_string(P_.e1[e]) + ") is not positive");
}

// Ψ at weights w (see the header): factor, solve for X, squared edge lengths.
double NewtonRun::evaluate(const std::vector<double>& w, Coords& X, std::vector<double>& l2, double& e_out,
                           double& s_out) {
  sys_.set_weight_floor_rel(
      edges_anchor_free_vertices(P_.e0, P_.e1, P_.fixed, [&](size_t e) { return w[e] > 0.0; }, uf_)
          ? 0.0
          : opt_.system.weight_floor_rel);
  sys_.factor(w, ctx_);
  sys_.solve(dims_, P_.fixed_pos, P_.b, 1.0, X);
  ++R_.factorizations;
  const auto& wa = sys_.assembled_weights();
  l2.resize(ne_);
  double en = 0, sn = 0;
  for (int32_t e : act_) {
    double s = 0;
    for (int k = 0; k < dims_; ++k) {
      const double d = X[k][P_.e1[e]] - X[k][P_.e0[e]];
      s += d * d;
    }
    l2[e] = s;
    en += 0.5 * wa[e] * s;
    sn += c_[e] * w[e];
  }
  if (!scale_free_)
    for (int k = 0; k < dims_; ++k)
      for (int32_t v = 0; v < nv_; ++v)
        if (!P_.fixed[v]) en += P_.b[k][v] * X[k][v];
  e_out = en;
  s_out = sn;
  return scale_free_ ? en - 0.5 * sn * sn : en - 0.5 * sn;
}

double NewtonRun::log_barrier(const std::vector<double>& w) const {
  double s = 0;
  for (int32_t e : act_) s += std::log(w[e]);
  return s;
}

// b = 0: Ψ_τ(tω) = tE - ½t²S² + τ Σ log(tω) is maximized at the t below, which
// leaves V as it is.
void NewtonRun::rescale(double tau) {
  if (!scale_free_ || !(S_ > 0) || !(E_ > 0)) return;
  const double t = (E_ + std::sqrt(E_ * E_ + 4 * S_ * S_ * tau * static_cast<double>(na_))) / (2 * S_ * S_);
  for (int32_t e : act_) om_[e] *= t;
  E_ *= t;
  S_ *= t;
  fscale_ *= t;
}

// out = -∇²Ψ_τ pv: one solve with the current factor, plus the barrier's τ / ω².
void NewtonRun::hessian_product(const std::vector<double>& pv, std::vector<double>& out) {
  for (int k = 0; k < dims_; ++k) std::fill(y_[k].begin(), y_[k].end(), 0.0);
  double cp = 0;
  for (size_t i = 0; i < na_; ++i) {
    if (pv[i] == 0.0) continue;
    const int32_t e = act_[i], a = P_.e0[e], b = P_.e1[e];
    for (int k = 0; k < dims_; ++k) {
      const double dv = pv[i] * (V_[k][a] - V_[k][b]);
      y_[k][a] += dv;
      y_[k][b] -= dv;
    }
    cp += c_[e] * pv[i];
  }
  sys_.solve(dims_, zero_pos_, y_, -1.0, z_);  // z_F = K^-1 y_F, z = 0 at fixed vertices
  ++R_.hessian_products;
  for (size_t i = 0; i < na_; ++i) {
    const int32_t e = act_[i], a = P_.e0[e], b = P_.e1[e];
    double s = 0;
    for (int k = 0; k < dims_; ++k) s += (V_[k][b] - V_[k][a]) * (z_[k][b] - z_[k][a]);
    out[i] = s / fscale_ + (scale_free_ ? c_[e] * cp : 0.0) + bar_[i] * pv[i];
  }
}

// The barrier weight τ for this mu, and at the current ω: the gradient g of
// Ψ_τ, the multipliers λ, the barrier curvature and the preconditioner.
// Returns the M-norm of g.
double NewtonRun::barrier_and_gradient(double mu, double& tau) {
  const double h = scale_free_ ? S_ : 0.5;
  // Barrier weight in the units of the problem: a positive weight's length
  // ratio is off by about mu / 2 on the central path.
  double cw = 0;
  for (int32_t e : act_) cw += c_[e] * om_[e];
  tau = mu * h * cw / static_cast<double>(std::max<size_t>(na_, 1));
  double gnorm = 0;
  for (size_t i = 0; i < na_; ++i) {
    const int32_t e = act_[i];
    g_[i] = 0.5 * l2_[e] - h * c_[e] + tau / om_[e];
    // Primal-dual: the barrier's curvature is λ_e / ω_e with the multiplier λ_e
    // of ω_e >= 0 kept as its own variable (λ ω = τ on the central path). After
    // τ drops, λ still carries the old multiplier and the step takes a vanishing
    // weight straight to its new central value (the primal τ / ω² would
    // overshoot below 0 and the step would be cut short).
    if (lam_[i] < 0) lam_[i] = tau / om_[e];
    lam_[i] = std::clamp(lam_[i], 1e-2 * tau / om_[e], 1e2 * tau / om_[e]);
    bar_[i] = lam_[i] / om_[e];
    // M = diag(||e||² / ω) bounds -∇²E (and is the plain update's scaling).
    Minv_[i] = 1.0 / (std::max(l2_[e], 1e-12 * c_[e]) / om_[e] + bar_[i]);
    gnorm += Minv_[i] * g_[i] * g_[i];
  }
  return std::sqrt(gnorm);
}

// Newton step x: preconditioned CG on -∇²Ψ_τ x = ∇Ψ_τ (positive definite), to
// relative residual eta or cg_max steps.
void NewtonRun::newton_direction(double eta, int cg_max) {
  std::fill(x_.begin(), x_.end(), 0.0);
  double rz = 0;
  for (size_t i = 0; i < na_; ++i) {
    r_[i] = g_[i];
    zr_[i] = Minv_[i] * r_[i];
    p_[i] = zr_[i];
    rz += r_[i] * zr_[i];
  }
  const double rz_stop = eta * eta * rz;
  for (int it = 0; it < cg_max && rz > 0; ++it) {
    hessian_product(p_, Ap_);
    double pAp = 0;
    for (size_t i = 0; i < na_; ++i) pAp += p_[i] * Ap_[i];
    if (!(pAp > 0.0)) {  // rounding: keep what we have, or the gradient step
      if (it == 0) x_ = p_;
      break;
    }
    const double alpha = rz / pAp;
    const double rz_new =
        cg_update(na_, alpha, p_.data(), Ap_.data(), Minv_.data(), x_.data(), r_.data(), zr_.data());
    if (rz_new <= rz_stop) break;
    const double beta = rz_new / rz;
    for (size_t i = 0; i < na_; ++i) p_[i] = zr_[i] + beta * p_[i];
    rz = rz_new;
  }
}

// Line search on Ψ_τ from the longest step that keeps every weight above
// newton_min_ratio of itself; should the Newton direction fail, the
// M-preconditioned gradient step (the plain update plus the barrier). The
// accepted trial leaves its weights in wt_, its embedding in Vt_ and l2t_.
LineSearchStep NewtonRun::line_search(double tau) {
  LineSearchStep step;
  double Et = 0, St = 0;
  const double psi = (scale_free_ ? E_ - 0.5 * S_ * S_ : E_ - 0.5 * S_) + tau * log_barrier(om_);
  const double psi_tol = 1e-12 * (std::abs(E_) + (scale_free_ ? 0.5 * S_ * S_ : 0.5 * S_) + std::abs(psi));
  for (int pass = 0; pass < 2 && !step.accepted; ++pass) {
    double tmax = 1.0;
    for (size_t i = 0; i < na_; ++i) {
      d_[i] = pass == 0 ? x_[i] : Minv_[i] * g_[i];
      if (d_[i] < 0) tmax = std::min(tmax, (1.0 - opt_.newton_min_ratio) * om_[act_[i]] / -d_[i]);
    }
    double t = tmax, pred_first = 0;
    for (int trial = 0; trial < opt_.newton_line_search && !step.accepted; ++trial, t *= 0.5) {
      wt_ = om_;
      double pred = 0;
      for (size_t i = 0; i < na_; ++i) {
        const int32_t e = act_[i];
        wt_[e] = om_[e] + t * d_[i];
        pred += g_[i] * t * d_[i];
      }
      if (trial == 0) pred_first = pred;
      const double psit = evaluate(wt_, Vt_, l2t_, Et, St) + tau * log_barrier(wt_);
      // Armijo; a step whose predicted gain is at rounding level is taken if it loses nothing.
      if ((pred_first > psi_tol && psit - psi >= 1e-4 * pred) ||
          (pred_first <= psi_tol && psit - psi >= -psi_tol)) {
        step.accepted = true;
        fscale_ = 1.0;
        step.first_trial = pass == 0 && trial == 0 && tmax >= 0.5;
        step.first_pass = pass == 0;
        step.t = t;
      }
    }
  }
  step.E = Et;
  step.S = St;
  return step;
}

// Dual step: λ + dλ with dλ = τ / ω - λ - (λ / ω) dω (linearized λ ω = τ),
// as far as it stays positive.
void NewtonRun::dual_step(double tau, bool newton_dir) {
  for (size_t i = 0; i < na_; ++i) {
    const int32_t e = act_[i];
    const double dw = wt_[e] - om_[e];
    const double target = newton_dir ? tau / om_[e] - bar_[i] * dw : tau / wt_[e];
    lam_[i] = target > 0 ? target : 0.5 * lam_[i];
  }
}

// Takes the line search's weights and embedding; returns the largest vertex
// change against the bounding-box diagonal of the new embedding.
double NewtonRun::accept_step(const LineSearchStep& step, double tau) {
  om_.swap(wt_);
  E_ = step.E;
  S_ = step.S;
  rescale(tau);
  const double diag = perfect_laplacian_detail::bbox_diagonal(dims_, Vt_, static_cast<size_t>(nv_));
  double change = 0;
  for (int32_t v = 0; v < nv_; ++v) {
    double s = 0;
    for (int q = 0; q < dims_; ++q) s += (Vt_[q][v] - V_[q][v]) * (Vt_[q][v] - V_[q][v]);
    change = std::max(change, s);
  }
  const double change_rel = diag > 0 ? std::sqrt(change) / diag : 0.0;
  V_.swap(Vt_);
  l2_.swap(l2t_);
  return change_rel;
}

void NewtonRun::iterate(Clock::time_point t_first) {
  double gnorm_first = -1;
  double mu = opt_.newton_barrier_start;
  // CG steps per iteration: newton_cg_max, fewer on large problems so that an
  // iteration's solves stay within a few factorizations' cost.
  const int cg_max = static_cast<int>(std::clamp<int64_t>(
      opt_.newton_cg_work / static_cast<int64_t>(std::max<size_t>(na_, 1)), opt_.newton_cg_min, opt_.newton_cg_max));
  const double mu_end = scale_free_ ? opt_.newton_barrier_end : opt_.newton_barrier_end_rhs;
  for (int k = 1; k <= opt_.max_iterations; ++k) {
    ctx_.check_cancel();
    const auto t_iter = Clock::now();
    R_.iterations = k;
    double tau = 0;
    const double gnorm = barrier_and_gradient(mu, tau);
    if (gnorm_first < 0) gnorm_first = gnorm;
    newton_direction(std::min(opt_.newton_forcing, gnorm_first > 0 ? std::sqrt(gnorm / gnorm_first) : 0.0), cg_max);
    const LineSearchStep step = line_search(tau);
    if (!step.accepted) {  // no ascent at all: rounding level; keep ω^(k-1)
      R_.converged = R_.last_change_rel < opt_.eps && mu <= mu_end;
      if (k == 1) R_.first_iter_s = seconds_since(t_first);
      break;
    }
    dual_step(tau, step.t > 0 && step.first_pass);
    const double change_rel = accept_step(step, tau);
    R_.change_history.push_back(change_rel);
    R_.last_change_rel = change_rel;
    if (k == 1)
      R_.first_iter_s = seconds_since(t_first);
    else
      later_s_.push_back(seconds_since(t_iter));
    ctx_.report(static_cast<double>(k) / opt_.max_iterations, "perfect Laplacian iterations");
    const bool at_end = mu <= mu_end;
    if (step.first_trial && at_end && change_rel < opt_.eps) {
      R_.converged = true;
      break;
    }
    // Follow the central path: a full Newton step lowers the barrier.
    if (step.first_trial) mu = std::max(mu_end, mu * opt_.newton_barrier_factor);
  }
}

// Weights that vanished along the central path (<= newton_zero_rel · max) are
// at their limit: exactly 0.
void NewtonRun::zero_vanished_weights() {
  double wmax = 0;
  for (int32_t e : act_) wmax = std::max(wmax, om_[e]);
  for (int32_t e : act_)
    if (om_[e] <= opt_.newton_zero_rel * wmax) om_[e] = 0.0;
}

// b = 0: the scale is free; the iterated weights get mean 1 (as at the start)
// so that passive edges (not iterated, initial weight) stay comparable.
void NewtonRun::normalize_iterated_mean() {
  if (!scale_free_ || na_ == 0) return;
  double s = 0;
  for (int32_t e : act_) s += om_[e];
  if (s > 0)
    for (int32_t e : act_) om_[e] *= static_cast<double>(na_) / s;
}

// Steady-state check (eq. 2.11): log length excess of the zero weights over
// the common ratio (1 with b != 0; sqrt(2 S) at the optimal scale with b = 0).
double NewtonRun::steady_state_violation() const {
  double mu2 = 1.0;
  if (scale_free_) {
    double num = 0, den = 0;
    for (int32_t e : act_) {
      num += om_[e] * l2_[e];
      den += om_[e] * c_[e];
    }
    mu2 = den > 0 ? num / den : 1.0;
  }
  std::vector<int32_t> positive_degree(static_cast<size_t>(nv_), 0);
  for (int32_t e : act_)
    if (om_[e] > 0) ++positive_degree[P_.e0[e]], ++positive_degree[P_.e1[e]];
  double worst = 0;
  bool any = false;
  for (int32_t e : act_) {
    if (om_[e] > 0) continue;
    const int32_t a = P_.e0[e], b = P_.e1[e];
    if ((!P_.fixed[a] && positive_degree[a] == 0) || (!P_.fixed[b] && positive_degree[b] == 0)) continue;
    const double g = 0.5 * std::log(std::max(l2_[e], 1e-300) / (c_[e] * mu2));
    worst = any ? std::max(worst, g) : g;
    any = true;
  }
  return worst;
}

// Final weights (unit 2-norm, vanished ones exactly 0) and the embedding.
void NewtonRun::finish() {
  zero_vanished_weights();
  normalize_iterated_mean();
  R_.kkt_violation = steady_state_violation();
  double norm = 0;
  for (double w : om_) norm += w * w;
  norm = std::sqrt(norm);
  R_.weights.resize(ne_);
  for (size_t e = 0; e < ne_; ++e) R_.weights[e] = norm > 0 ? om_[e] / norm : 0.0;
  R_.rhs_scale = norm > 0 ? 1.0 / norm : 1.0;
  R_.pos = std::move(V_);
  R_.iter_s = perfect_laplacian_detail::median(later_s_);
}

}  // namespace

PerfectLaplacianResult run_perfect_laplacian_newton(const PerfectLaplacianProblem& P,
                                                    const PerfectLaplacianOptions& opt, const RunContext& ctx) {
  PerfectLaplacianResult R;
  const auto t_first = Clock::now();
  NewtonRun run(P, opt, ctx, R);
  run.iterate(t_first);
  run.finish();
  return R;
}

}  // namespace locus
