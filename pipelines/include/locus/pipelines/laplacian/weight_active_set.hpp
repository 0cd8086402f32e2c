// Active set of the edge weights of Algorithm 1 (thesis §2.3.3, eq. 2.11).
//
// Where a mesh admits no perfect Laplacian (non-regular triangulations, planar
// polygon meshes with non-convex faces, most meshes in space) the steady state
// sets some weights to 0 and scales the lengths of all others by one common
// factor μ^-1. The multiplicative update (eq. 2.8) only approaches that limit:
// such a weight shrinks by a factor exp(g_e) < 1 per iteration, with g_e the
// edge's log-length excess over the common ratio (g_e = log(||e|| / ||ê||) -
// log μ^-1), often only 0.3-3% per iteration, and the vertices keep moving by
// O(ω_e · g_e) long after everything else has settled (hundreds of iterations
// on planar polygon meshes with non-convex faces; docs/perfect_laplacian.md).
//
// Why the limit is well defined: the steady states that are stable under a small
// positive perturbation of a zero weight are exactly the maximizers of the
// CONCAVE function Φ(ω) = min_V ½ Σ_e ω_e ||e_V||² + <b, V> - ½ Σ_e ω_e ||ê_e||²
// (a minimum of functions affine in ω; ∂Φ/∂ω_e = ½(||e||² - ||ê||²) by the
// envelope theorem) over ω >= 0 (with b = 0 over Σ ω_e ||ê_e||² = 1): its KKT
// conditions say ||e|| / ||ê|| equals one common ratio where ω_e > 0 and does
// not exceed it where ω_e = 0. That is eq. 2.11 plus "a zero weight would not grow
// back", and it is what the active set below converges to and checks.
//
// The active set:
//  * Decay is established when g_e < -min_rate for `window` consecutive
//    iterations without fading (|g_e| stays above (1 - fade) · its value when
//    the streak began: a weight converging to a positive value has a residual
//    that shrinks geometrically). Such an edge is then PUSHED: its log weight
//    moves by 2^j · g_e in the j-th pushed iteration (at most max_log_step), a
//    speculative extrapolation of its own decay that reaches the floor in tens
//    of iterations instead of thousands. The acceleration of the other weights
//    treats a pushed edge as converged (its residual is left out).
//  * Vanishing vertices. Where EVERY active edge of a free vertex decays, the
//    vertex is losing all its weights (its position depends only on their
//    ratios, and in the plain iteration they end up decaying at one common
//    rate). Pushing them one by one would change those ratios and throw the
//    vertex about; instead all its edges get one common push (growing like
//    the individual ones, from the mean residual of its edges), so the vertex
//    stays where it is while its weights vanish together.
//  * Undo: if a pushed edge's residual turns positive (the rest of the mesh has
//    moved and now wants the edge back), its log weight returns to its value
//    when the decay began, and it is an ordinary edge again.
//  * Drop: a pushed weight below vanish_rel · (strongest active weight at each
//    free end) becomes exactly 0 and leaves the iteration (the embedding system
//    keeps the entry in its pattern with value 0, so the symbolic factorization
//    stays).
//  * Check: at convergence, dropped edges with g_e > kkt_tol violate the KKT
//    condition; they come back at their pre-decay weight and the iteration
//    resumes. An edge whose free end has no active edge left is exempt: that
//    vertex is not determined by the steady state (eq. 2.11 holds with all its
//    weights 0; the embedding system's floor places it at the average of its
//    neighbors). An edge is dropped at most max_drops times, so the set cannot
//    cycle.
//
// Edges with both ends fixed do not enter the embedding system at all (eq. 2.4
// has no row for fixed vertices): they are "passive", never iterated, never
// dropped.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace locus {

enum class WeightState : uint8_t { active = 0, dropped = 1, passive = 2 };

struct WeightActiveSetOptions {
  // Defaults from a sweep of the "convergence study" in
  // tests/pipelines/laplacian/perfect_laplacian.cpp: shorter windows push edges
  // whose residual later changes sign (chaotic iterates); these converged the
  // most (docs/perfect_laplacian.md).
  int window = 60;              // iterations of established decay before an edge is pushed
  double min_rate = 2e-3;       // decay: g_e < -min_rate (log-length excess per iteration)
  double fade = 0.3;            // decay fades when |g_e| < (1 - fade) · |g_e at the streak start|
  double max_log_step = 4.0;    // largest push of a log weight in one iteration
  double push_growth = 2.0;     // the push grows by this factor per pushed iteration
  bool restore_on_undo = true;  // an undone push restores the pre-decay weight
  double vanish_rel = 1e-10;    // pushed weight <= this · (strongest active weight at each free end): dropped
  double kkt_tol = 1e-4;        // a dropped edge with g_e > kkt_tol at convergence comes back
  int max_drops = 3;            // per edge; after that it stays active for good
};

// True when the edges e with use(e) (of e0/e1, ne of them) tie every free vertex
// to a fixed one: union-find with all fixed vertices in one class. Then an
// embedding system assembled from those edges alone is positive definite.
// parent: scratch, resized to nv + 1 (nv = fixed.size()).
template <class UseEdge>
bool edges_anchor_free_vertices(std::span<const int32_t> e0, std::span<const int32_t> e1,
                                std::span<const uint8_t> fixed, UseEdge use, std::vector<int32_t>& parent) {
  const int32_t nv = static_cast<int32_t>(fixed.size());
  parent.resize(static_cast<size_t>(nv) + 1);
  for (int32_t v = 0; v <= nv; ++v) parent[v] = v;
  auto find = [&](int32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  auto unite = [&](int32_t a, int32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  for (int32_t v = 0; v < nv; ++v)
    if (fixed[v]) unite(v, nv);
  for (size_t e = 0; e < e0.size(); ++e)
    if (use(e)) unite(e0[e], e1[e]);
  const int32_t anchor = find(nv);
  for (int32_t v = 0; v < nv; ++v)
    if (find(v) != anchor) return false;
  return true;
}

class WeightActiveSet {
 public:
  // e0/e1: the edges; fixed[v] != 0 for vertices held fixed by the embedding system.
  WeightActiveSet(int32_t nv, std::span<const int32_t> e0, std::span<const int32_t> e1,
                  std::span<const uint8_t> fixed, const WeightActiveSetOptions& opt = {});

  WeightState state(size_t e) const { return state_[e]; }
  // Indices of the active edges (pushed ones included), increasing.
  const std::vector<int32_t>& active() const { return active_; }
  bool pushed(size_t e) const { return push_[e] > 0; }
  int64_t num_dropped() const { return num_dropped_; }
  int64_t num_pushes() const { return num_pushes_; }    // pushes started so far
  int64_t num_revived() const { return num_revived_; }  // revivals and undone pushes so far
  // True when the active edges alone tie every free vertex to a fixed one: then
  // the embedding system is positive definite with the dropped weights at exactly
  // 0 and needs no positivity floor.
  bool anchored() const { return anchored_; }

  // After each solve, with the residual g, the weights ω of that solve (any
  // common scale) and the log weights U (per edge): updates the decay streaks,
  // starts, continues or undoes pushes (U of undone pushes is restored), drops
  // vanished pushed weights. Returns how many edges were dropped.
  int32_t observe(std::span<const double> g, std::span<const double> w, std::span<double> U);

  // The push of a pushed edge this iteration (a negative change of its log weight).
  double push_step(size_t e, double g_e) const;

  // Drops edge e now (its weight reached the caller's floor). Returns false, and
  // leaves it active, when the edge has been dropped max_drops times already.
  bool drop(size_t e);

  // At convergence: revives the dropped edges with g_e > kkt_tol whose free ends
  // still have active edges, restoring their pre-decay log weight in U; returns
  // how many.
  int32_t revive_violators(std::span<const double> g, std::span<double> U);

  // max g_e over the dropped edges that revive_violators checks (-infinity if
  // none): <= kkt_tol in a steady state.
  double max_violation(std::span<const double> g) const;

 private:
  void rebuild_active();
  bool exempt(size_t e) const;  // a free end without active edges

  std::vector<int32_t> e0_, e1_;
  std::vector<uint8_t> fixed_;
  WeightActiveSetOptions opt_;
  std::vector<WeightState> state_;
  std::vector<int32_t> active_;
  std::vector<int32_t> streak_;    // consecutive iterations of established decay
  std::vector<int32_t> push_;      // pushed iterations so far (0: not pushed)
  std::vector<double> g_start_;    // g_e when the streak began
  std::vector<double> u_start_;    // log weight when the streak began (restored on undo / revival)
  std::vector<uint8_t> drops_;     // per edge: times dropped
  std::vector<int32_t> active_degree_;  // per vertex: active edges
  std::vector<double> vmax_;       // workspace: strongest active weight per vertex
  std::vector<int32_t> vpush_;     // per vertex: consecutive iterations with every active edge decaying
  std::vector<double> vstep_;      // per vertex: the common push of its edges this iteration (0: none)
  bool anchored_ = false;
  int64_t num_dropped_ = 0, num_revived_ = 0, num_pushes_ = 0;
};

}  // namespace locus
