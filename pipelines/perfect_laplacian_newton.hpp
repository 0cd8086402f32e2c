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
// ratio where ω_e > 0 and does not exceed it where ω_e = 0.
//
// Why Newton: the plain update is the gradient step preconditioned by
// M = diag(||e||² / ω_e) (to first order, ω_e · log(||e|| / ||ê||)); it converges
// linearly with a rate that goes to 1 where weights vanish (hundreds to thousands
// of iterations), and near the vanishing weights heuristic extrapolation is
// fragile. The Hessian of E is available exactly and cheaply as a product:
//
//     -∇²E v = Q,  Q_e = e_V · (z_q - z_p),  K z = y,  y_i = Σ_{e ∋ i} v_e (V_i - V_j),
//
// one solve with the factor of the iteration (no new factorization). So each
// iteration: factor K(ω) once, solve for V, then preconditioned conjugate
// gradients (preconditioner M, which also bounds the Hessian: -∇²E <= M) for the
// Newton step on the edges that are not held at 0, a projection onto ω >= 0
// (weights that cross 0 become exact zeros: the §2.3.3 steady state in finitely
// many steps), and an Armijo line search on Ψ (each trial one factorization).
// Dropped weights come back by themselves when their gradient turns positive
// (the KKT check is part of every step). Convergence, as for Algorithm 1: the
// largest vertex change of an iteration < eps · bounding-box diagonal, after a
// full Newton step.
#pragma once
#include "pipelines/perfect_laplacian.hpp"

namespace locus {

// Called by run_perfect_laplacian (after validating the problem) when
// opt.method == PerfectLaplacianMethod::newton.
PerfectLaplacianResult run_perfect_laplacian_newton(const PerfectLaplacianProblem& problem,
                                                    const PerfectLaplacianOptions& opt, const RunContext& ctx);

}  // namespace locus
