// Projected Newton method for the steady state of Algorithm 1; see
// perfect_laplacian_newton.hpp for the objective, the Hessian product and why.
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

}  // namespace

PerfectLaplacianResult run_perfect_laplacian_newton(const PerfectLaplacianProblem& P,
                                                    const PerfectLaplacianOptions& opt, const RunContext& ctx) {
  const int32_t nv = P.nv;
  const size_t ne = P.e0.size();
  const int dims = P.dims;
  PerfectLaplacianResult R;
  const auto t_first = Clock::now();
  EmbeddingSystem sys(nv, P.e0, P.e1, P.fixed, opt.system);
  R.order_s = sys.order_s();
  R.analyze_s = sys.analyze_s();

  const bool scale_free = perfect_laplacian_detail::scale_free(P);
  R.scale_free = scale_free;

  // Iterated edges: those with a free end (both ends fixed: no row of eq. 2.4).
  std::vector<int32_t> act;
  for (size_t e = 0; e < ne; ++e)
    if (!(P.fixed[P.e0[e]] && P.fixed[P.e1[e]])) act.push_back(static_cast<int32_t>(e));
  const size_t na = act.size();
  std::vector<double> c(ne);  // ||ê_e||²
  for (size_t e = 0; e < ne; ++e) c[e] = P.target_length[e] * P.target_length[e];
  std::vector<double> om(ne, 1.0);  // raw weights ω (Algorithm 1 starts at 1)
  if (!P.initial_weights.empty()) {
    om = P.initial_weights;
    for (size_t e = 0; e < ne; ++e)
      if (!(om[e] > 0.0) || !std::isfinite(om[e]))
        fail(ErrorCode::BadInput, "perfect Laplacian: initial weight of edge " + std::to_string(e) + " (" +
                                      std::to_string(P.e0[e]) + ", " + std::to_string(P.e1[e]) + ") is not positive");
  }

  std::vector<int32_t> uf;
  Coords zero_pos;
  for (int k = 0; k < dims; ++k) zero_pos[k].assign(static_cast<size_t>(nv), 0.0);

  // Ψ at weights w (see the header): factor, solve for X, squared edge lengths.
  double E = 0, S = 0;
  auto evaluate = [&](const std::vector<double>& w, Coords& X, std::vector<double>& l2, double& e_out,
                      double& s_out) {
    sys.set_weight_floor_rel(edges_anchor_free_vertices(P.e0, P.e1, P.fixed, [&](size_t e) { return w[e] > 0.0; }, uf) ? 0.0
                                                                                   : opt.system.weight_floor_rel);
    sys.factor(w, ctx);
    sys.solve(dims, P.fixed_pos, P.b, 1.0, X);
    ++R.factorizations;
    const auto& wa = sys.assembled_weights();
    l2.resize(ne);
    double en = 0, sn = 0;
    for (int32_t e : act) {
      double s = 0;
      for (int k = 0; k < dims; ++k) {
        const double d = X[k][P.e1[e]] - X[k][P.e0[e]];
        s += d * d;
      }
      l2[e] = s;
      en += 0.5 * wa[e] * s;
      sn += c[e] * w[e];
    }
    if (!scale_free)
      for (int k = 0; k < dims; ++k)
        for (int32_t v = 0; v < nv; ++v)
          if (!P.fixed[v]) en += P.b[k][v] * X[k][v];
    e_out = en;
    s_out = sn;
    return scale_free ? en - 0.5 * sn * sn : en - 0.5 * sn;
  };
  auto log_barrier = [&](const std::vector<double>& w) {
    double s = 0;
    for (int32_t e : act) s += std::log(w[e]);
    return s;
  };
  // b = 0: Ψ_τ(tω) = tE - ½t²S² + τ Σ log(tω) is maximized at the t below, which
  // leaves V as it is. The factor in sys is then K(ω / fscale): K^-1 scales by 1 / fscale.
  double fscale = 1.0;
  auto rescale = [&](double tau) {
    if (!scale_free || !(S > 0) || !(E > 0)) return;
    const double t = (E + std::sqrt(E * E + 4 * S * S * tau * static_cast<double>(na))) / (2 * S * S);
    for (int32_t e : act) om[e] *= t;
    E *= t;
    S *= t;
    fscale *= t;
  };

  Coords V, Vt;
  std::vector<double> l2, l2t;
  evaluate(om, V, l2, E, S);
  rescale(0.0);

  // Per iterated edge (index into act): gradient, preconditioner, CG vectors.
  std::vector<double> lam(na, -1.0), g(na), Minv(na), bar(na), x(na), r(na), zr(na), p(na), Ap(na), d(na), wt(ne);
  Coords y, z;
  for (int k = 0; k < dims; ++k) y[k].assign(static_cast<size_t>(nv), 0.0);
  // Ap = -∇²Ψ_τ p: one solve with the current factor, plus the barrier's τ / ω².
  auto hessian_product = [&](const std::vector<double>& pv, std::vector<double>& out) {
    for (int k = 0; k < dims; ++k) std::fill(y[k].begin(), y[k].end(), 0.0);
    double cp = 0;
    for (size_t i = 0; i < na; ++i) {
      if (pv[i] == 0.0) continue;
      const int32_t e = act[i], a = P.e0[e], b = P.e1[e];
      for (int k = 0; k < dims; ++k) {
        const double dv = pv[i] * (V[k][a] - V[k][b]);
        y[k][a] += dv;
        y[k][b] -= dv;
      }
      cp += c[e] * pv[i];
    }
    sys.solve(dims, zero_pos, y, -1.0, z);  // z_F = K^-1 y_F, z = 0 at fixed vertices
    ++R.hessian_products;
    for (size_t i = 0; i < na; ++i) {
      const int32_t e = act[i], a = P.e0[e], b = P.e1[e];
      double s = 0;
      for (int k = 0; k < dims; ++k) s += (V[k][b] - V[k][a]) * (z[k][b] - z[k][a]);
      out[i] = s / fscale + (scale_free ? c[e] * cp : 0.0) + bar[i] * pv[i];
    }
  };

  std::vector<double> later_s;
  double gnorm_first = -1;
  double mu = opt.newton_barrier_start;
  // CG steps per iteration: newton_cg_max, fewer on large problems so that an
  // iteration's solves stay within a few factorizations' cost.
  const int cg_max = static_cast<int>(std::clamp<int64_t>(
      opt.newton_cg_work / static_cast<int64_t>(std::max<size_t>(na, 1)), opt.newton_cg_min, opt.newton_cg_max));
  const double mu_end = scale_free ? opt.newton_barrier_end : opt.newton_barrier_end_rhs;
  for (int k = 1; k <= opt.max_iterations; ++k) {
    ctx.check_cancel();
    const auto t_iter = Clock::now();
    R.iterations = k;
    const double h = scale_free ? S : 0.5;
    // Barrier weight in the units of the problem: a positive weight's length
    // ratio is off by about mu / 2 on the central path.
    double cw = 0;
    for (int32_t e : act) cw += c[e] * om[e];
    const double tau = mu * h * cw / static_cast<double>(std::max<size_t>(na, 1));
    double gnorm = 0;
    for (size_t i = 0; i < na; ++i) {
      const int32_t e = act[i];
      g[i] = 0.5 * l2[e] - h * c[e] + tau / om[e];
      // Primal-dual: the barrier's curvature is λ_e / ω_e with the multiplier λ_e
      // of ω_e >= 0 kept as its own variable (λ ω = τ on the central path). After
      // τ drops, λ still carries the old multiplier and the step takes a vanishing
      // weight straight to its new central value (the primal τ / ω² would
      // overshoot below 0 and the step would be cut short).
      if (lam[i] < 0) lam[i] = tau / om[e];
      lam[i] = std::clamp(lam[i], 1e-2 * tau / om[e], 1e2 * tau / om[e]);
      bar[i] = lam[i] / om[e];
      // M = diag(||e||² / ω) bounds -∇²E (and is the plain update's scaling).
      Minv[i] = 1.0 / (std::max(l2[e], 1e-12 * c[e]) / om[e] + bar[i]);
      gnorm += Minv[i] * g[i] * g[i];
    }
    gnorm = std::sqrt(gnorm);
    if (gnorm_first < 0) gnorm_first = gnorm;

    // Newton step: preconditioned CG on -∇²Ψ_τ d = ∇Ψ_τ (positive definite).
    const double eta = std::min(opt.newton_forcing, gnorm_first > 0 ? std::sqrt(gnorm / gnorm_first) : 0.0);
    std::fill(x.begin(), x.end(), 0.0);
    double rz = 0;
    for (size_t i = 0; i < na; ++i) {
      r[i] = g[i];
      zr[i] = Minv[i] * r[i];
      p[i] = zr[i];
      rz += r[i] * zr[i];
    }
    const double rz_stop = eta * eta * rz;
    for (int it = 0; it < cg_max && rz > 0; ++it) {
      hessian_product(p, Ap);
      double pAp = 0;
      for (size_t i = 0; i < na; ++i) pAp += p[i] * Ap[i];
      if (!(pAp > 0.0)) {  // rounding: keep what we have, or the gradient step
        if (it == 0) x = p;
        break;
      }
      const double alpha = rz / pAp;
      double rz_new = 0;
      for (size_t i = 0; i < na; ++i) {
        x[i] += alpha * p[i];
        r[i] -= alpha * Ap[i];
        zr[i] = Minv[i] * r[i];
        rz_new += r[i] * zr[i];
      }
      if (rz_new <= rz_stop) break;
      const double beta = rz_new / rz;
      for (size_t i = 0; i < na; ++i) p[i] = zr[i] + beta * p[i];
      rz = rz_new;
    }

    // Line search on Ψ_τ from the longest step that keeps every weight above
    // newton_min_ratio of itself; should the Newton direction fail, the
    // M-preconditioned gradient step (the plain update plus the barrier).
    bool accepted = false, first_trial = false, first_pass = false;
    double Et = 0, St = 0, t_taken = 0;
    const double psi = (scale_free ? E - 0.5 * S * S : E - 0.5 * S) + tau * log_barrier(om);
    const double psi_tol = 1e-12 * (std::abs(E) + (scale_free ? 0.5 * S * S : 0.5 * S) + std::abs(psi));
    for (int pass = 0; pass < 2 && !accepted; ++pass) {
      double tmax = 1.0;
      for (size_t i = 0; i < na; ++i) {
        d[i] = pass == 0 ? x[i] : Minv[i] * g[i];
        if (d[i] < 0) tmax = std::min(tmax, (1.0 - opt.newton_min_ratio) * om[act[i]] / -d[i]);
      }
      double t = tmax, pred_first = 0;
      for (int trial = 0; trial < opt.newton_line_search && !accepted; ++trial, t *= 0.5) {
        wt = om;
        double pred = 0;
        for (size_t i = 0; i < na; ++i) {
          const int32_t e = act[i];
          wt[e] = om[e] + t * d[i];
          pred += g[i] * t * d[i];
        }
        if (trial == 0) pred_first = pred;
        const double psit = evaluate(wt, Vt, l2t, Et, St) + tau * log_barrier(wt);
        // Armijo; a step whose predicted gain is at rounding level is taken if it loses nothing.
        if ((pred_first > psi_tol && psit - psi >= 1e-4 * pred) ||
            (pred_first <= psi_tol && psit - psi >= -psi_tol)) {
          accepted = true;
          fscale = 1.0;
          first_trial = pass == 0 && trial == 0 && tmax >= 0.5;
          first_pass = pass == 0;
          t_taken = t;
        }
      }
    }
    if (!accepted) {  // no ascent at all: rounding level; keep ω^(k-1)
      R.converged = R.last_change_rel < opt.eps && mu <= mu_end;
      if (k == 1) R.first_iter_s = seconds_since(t_first);
      break;
    }
    // Dual step: λ + dλ with dλ = τ / ω - λ - (λ / ω) dω (linearized λ ω = τ),
    // as far as it stays positive.
    {
      const bool newton_dir = t_taken > 0 && first_pass;
      for (size_t i = 0; i < na; ++i) {
        const int32_t e = act[i];
        const double dw = wt[e] - om[e];
        const double target = newton_dir ? tau / om[e] - bar[i] * dw : tau / wt[e];
        lam[i] = target > 0 ? target : 0.5 * lam[i];
      }
    }
    om.swap(wt);
    E = Et;
    S = St;
    rescale(tau);

    const double diag = perfect_laplacian_detail::bbox_diagonal(dims, Vt, static_cast<size_t>(nv));
    double change = 0;
    for (int32_t v = 0; v < nv; ++v) {
      double s = 0;
      for (int q = 0; q < dims; ++q) s += (Vt[q][v] - V[q][v]) * (Vt[q][v] - V[q][v]);
      change = std::max(change, s);
    }
    const double change_rel = diag > 0 ? std::sqrt(change) / diag : 0.0;
    V.swap(Vt);
    l2.swap(l2t);
    R.change_history.push_back(change_rel);
    R.last_change_rel = change_rel;
    if (k == 1)
      R.first_iter_s = seconds_since(t_first);
    else
      later_s.push_back(seconds_since(t_iter));
    ctx.report(static_cast<double>(k) / opt.max_iterations, "perfect Laplacian iterations");
    const bool at_end = mu <= mu_end;
    if (first_trial && at_end && change_rel < opt.eps) {
      R.converged = true;
      break;
    }
    // Follow the central path: a full Newton step lowers the barrier.
    if (first_trial) mu = std::max(mu_end, mu * opt.newton_barrier_factor);
  }

  // Weights that vanished along the central path (<= newton_zero_rel · max) are
  // at their limit: exactly 0.
  {
    double wmax = 0;
    for (int32_t e : act) wmax = std::max(wmax, om[e]);
    for (int32_t e : act)
      if (om[e] <= opt.newton_zero_rel * wmax) om[e] = 0.0;
  }
  // b = 0: the scale is free; the iterated weights get mean 1 (as at the start)
  // so that passive edges (not iterated, initial weight) stay comparable.
  if (scale_free && na > 0) {
    double s = 0;
    for (int32_t e : act) s += om[e];
    if (s > 0)
      for (int32_t e : act) om[e] *= static_cast<double>(na) / s;
  }
  // Steady-state check (eq. 2.11): log length excess of the zero weights over
  // the common ratio (1 with b != 0; sqrt(2 S) at the optimal scale with b = 0).
  {
    double mu2 = 1.0;
    if (scale_free) {
      double num = 0, den = 0;
      for (int32_t e : act) {
        num += om[e] * l2[e];
        den += om[e] * c[e];
      }
      mu2 = den > 0 ? num / den : 1.0;
    }
    std::vector<int32_t> positive_degree(static_cast<size_t>(nv), 0);
    for (int32_t e : act)
      if (om[e] > 0) ++positive_degree[P.e0[e]], ++positive_degree[P.e1[e]];
    double worst = 0;
    bool any = false;
    for (int32_t e : act) {
      if (om[e] > 0) continue;
      const int32_t a = P.e0[e], b = P.e1[e];
      if ((!P.fixed[a] && positive_degree[a] == 0) || (!P.fixed[b] && positive_degree[b] == 0)) continue;
      const double g = 0.5 * std::log(std::max(l2[e], 1e-300) / (c[e] * mu2));
      worst = any ? std::max(worst, g) : g;
      any = true;
    }
    R.kkt_violation = worst;
  }
  double norm = 0;
  for (double w : om) norm += w * w;
  norm = std::sqrt(norm);
  R.weights.resize(ne);
  for (size_t e = 0; e < ne; ++e) R.weights[e] = norm > 0 ? om[e] / norm : 0.0;
  R.rhs_scale = norm > 0 ? 1.0 / norm : 1.0;
  R.pos = std::move(V);
  R.iter_s = perfect_laplacian_detail::median(later_s);
  return R;
}

}  // namespace locus
