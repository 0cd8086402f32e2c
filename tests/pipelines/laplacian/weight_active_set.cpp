// Tests for pipelines/weight_active_set on synthetic residual sequences whose
// fate is known in advance: a steady decay (pushed after the window, then
// dropped once its weight has vanished), a geometrically converging residual
// (never pushed), edges between fixed vertices (passive), an undone push, the
// steady-state check (a dropped edge whose residual turns positive comes back
// at its pre-decay weight) and the bound on repeated drops.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "locus/pipelines/laplacian/weight_active_set.hpp"

using namespace locus;

namespace {

// Normalized weights from log weights, as Algorithm 1 assembles them (dropped: 0).
std::vector<double> weights(const WeightActiveSet& S, const std::vector<double>& U) {
  std::vector<double> w(U.size());
  for (size_t e = 0; e < U.size(); ++e) w[e] = S.state(e) == WeightState::dropped ? 0.0 : std::exp(U[e]);
  return w;
}

}  // namespace

TEST_CASE("weight active set: steady decay is pushed and dropped; convergence and passive edges are not") {
  // Path 0-1-2-3 plus edge 0-3; vertices 0 and 3 fixed, so edge 0-3 is passive.
  const std::vector<int32_t> e0{0, 1, 2, 0}, e1{1, 2, 3, 3};
  const std::vector<uint8_t> fixed{1, 0, 0, 1};
  WeightActiveSetOptions o;  // window 5, min_rate 1e-3, vanish_rel 1e-10
  WeightActiveSet S(4, e0, e1, fixed, o);
  CHECK(S.state(3) == WeightState::passive);
  CHECK(S.active().size() == 3);
  std::vector<double> U{0.0, 0.0, 0.0, 0.0};
  int pushed_at = -1, dropped_at = -1;
  for (int k = 0; k < 100 && dropped_at < 0; ++k) {
    const std::vector<double> g{-0.5 * std::pow(0.5, k), -0.01, -0.2 * std::pow(0.4, k), -1.0};
    const std::vector<double> w = weights(S, U);
    if (S.observe(g, w, U) > 0) dropped_at = k;
    if (S.pushed(1) && pushed_at < 0) pushed_at = k;
    // The caller's step: plain for ordinary edges, the push for pushed ones.
    for (int32_t e : S.active()) U[e] += S.pushed(e) ? S.push_step(e, g[e]) : g[e];
  }
  CHECK(pushed_at == o.window - 1);  // the window-th observation of the decay
  CHECK(dropped_at > pushed_at);
  CHECK(dropped_at < pushed_at + 20);  // log(1e-10) / 0.01 = 2300 plain iterations
  CHECK(S.state(1) == WeightState::dropped);
  CHECK(S.state(0) == WeightState::active);  // converging, however slowly
  CHECK(S.state(2) == WeightState::active);
  CHECK(S.state(3) == WeightState::passive);
  CHECK(S.active() == std::vector<int32_t>{0, 2});
  CHECK(S.num_dropped() == 1);
  CHECK(S.anchored());  // vertex 1 is still tied to fixed 0, vertex 2 to fixed 3
}

TEST_CASE("weight active set: undone pushes, revival at the pre-decay weight, bounded drops") {
  const std::vector<int32_t> e0{0, 1, 1}, e1{1, 2, 3};
  const std::vector<uint8_t> fixed{1, 0, 1, 1};
  WeightActiveSetOptions o;
  o.max_drops = 2;
  WeightActiveSet S(4, e0, e1, fixed, o);
  std::vector<double> U{0.0, 0.0, 0.0};
  std::vector<double> g{-0.05, 0.0, 0.0};
  for (int k = 0; k < o.window; ++k) S.observe(g, weights(S, U), U);
  REQUIRE(S.pushed(0));
  U[0] = -7.0;  // pushed down meanwhile
  g = {+0.01, 0.0, 0.0};  // the rest moved: edge 0 wants to grow
  S.observe(g, weights(S, U), U);
  CHECK_FALSE(S.pushed(0));
  CHECK(U[0] == 0.0);  // back at its weight when the decay began
  CHECK(S.num_revived() == 1);

  // Dropped edge: the steady-state check revives it only when it would grow back.
  CHECK(S.drop(0));
  CHECK(S.anchored());  // vertex 1 keeps edges 1 and 2
  g = {-1e-3, 0.0, 0.0};
  CHECK(S.revive_violators(g, U) == 0);
  CHECK(S.max_violation(g) == doctest::Approx(-1e-3));
  g = {2 * o.kkt_tol, 0.0, 0.0};
  U[0] = -30;
  CHECK(S.revive_violators(g, U) == 1);
  CHECK(S.state(0) == WeightState::active);
  CHECK(U[0] == 0.0);
  // Second drop uses up max_drops = 2: after that drop() refuses.
  CHECK(S.drop(0));
  CHECK(S.revive_violators(g, U) == 1);
  CHECK_FALSE(S.drop(0));
  // A free vertex with no active edge left exempts its edges from the check.
  CHECK(S.drop(1));
  WeightActiveSet T(4, e0, e1, fixed, o);
  CHECK(T.drop(0));
  CHECK(T.drop(1));
  CHECK(T.drop(2));  // vertex 1 isolated
  CHECK_FALSE(T.anchored());
  CHECK(T.revive_violators(std::vector<double>{1.0, 1.0, 1.0}, U) == 0);
}
