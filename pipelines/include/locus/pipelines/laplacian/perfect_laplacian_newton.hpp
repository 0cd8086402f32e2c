// Steady state of Algorithm 1 by a projected Newton method on its concave dual
// (thesis §2.3.3, eq. 2.11; see weight_active_set.hpp for why the steady state
// is the maximizer of a concave function).
//
// With E(ω) = min_V ½ Σ_e ω_e ||e_V||² + <b, V> (fixed vertices held, the energy
// whose minimizer is the embedding of eq. 2.4 / 2.10), E is concave in ω (a
// minimum of affine functions) with ∂E/∂ω_e = ½ ||e_V||². The steady state of
// the multiplicative update (eq. 2.8) is the maximizer over ω >= 0 of
//
//     Ψ(ω) = E(ω) - ½ Σ_e ω_e ||ê_e||²      (b != 0: edge ratios -> 1), or
//     Ψ(ω) = E(ω) - ½ (Σ_e ω_e ||ê_e||²)²   (b = 0: E is 1-homogeneous, only a
//                                             common ratio μ is fixed, eq. 2.11),
//
// whose KKT conditions are exactly eq. 2.11: ||e|| / ||ê|| equals one common
// ratio where ω_e > 0 and does not exceed it where ω_e = 0 (with b = 0, the
// scale S = Σ ω_e ||ê_e||² sets that ratio to sqrt(2 S)).
//
// Why Newton: the plain update is the gradient step preconditioned by
// M = diag(||e||² / ω_e) (to first order, ω_e · log(||e|| / ||ê||)); it converges
// linearly with a rate that goes to 1 where weights vanish (hundreds to thousands
// of iterations), and heuristic extrapolation of the vanishing weights proved
// fragile on polygon meshes with non-convex faces (figures in
// docs/perfect_laplacian.md). The Hessian of E is available exactly and
// cheaply as a product:
//
//     -∇²E v = Q,  Q_e = e_V · (z_q - z_p),  K z = y,  y_i = Σ_{e ∋ i} v_e (V_i - V_j),
//
// one solve with the factor of the iteration (no new factorization).
//
// Why an interior point (log barrier τ Σ log ω_e, τ -> 0): where a perfect
// Laplacian exists the maximizers of Ψ are not unique (Ψ is flat along the
// equilibrium stresses of the input), so a plain projected Newton method runs
// to the boundary of that set and ends with zero weights, or takes infinite
// steps along it. The barrier makes the maximizer unique and interior (the
// weights stay positive wherever some maximizer has them positive) and lets
// vanishing weights approach 0 like τ / |∂Ψ/∂ω_e| (the §2.3.3 steady state)
// instead of at the plain update's slow rate; no active-set heuristics.
//
// Each iteration: factor K(ω) once, solve for V, preconditioned conjugate
// gradients (preconditioner M plus the barrier's curvature) for the primal-dual
// Newton step of the barrier problem (the multiplier λ_e of ω_e >= 0 is kept as
// its own variable, so that after τ drops a vanishing weight goes straight to
// its new central value), the longest step keeping every weight above
// newton_min_ratio of itself, and an Armijo line search on Ψ + τ Σ log ω (each
// trial one factorization); should Newton's direction fail, the M-preconditioned
// gradient step. A full step lowers τ by newton_barrier_factor. Convergence, as
// for Algorithm 1: the largest vertex change of an iteration < eps · bounding-box
// diagonal, after a full Newton step with τ at its end value. Weights that end
// below newton_zero_rel · max have vanished and are returned as exact zeros.
#pragma once
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"

namespace locus {

// Called by run_perfect_laplacian (after validating the problem) when
// opt.method == PerfectLaplacianMethod::newton.
PerfectLaplacianResult run_perfect_laplacian_newton(const PerfectLaplacianProblem& problem,
                                                    const PerfectLaplacianOptions& opt, const RunContext& ctx);

}  // namespace locus
