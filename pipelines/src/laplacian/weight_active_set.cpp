// Active set of the edge weights of Algorithm 1; see weight_active_set.hpp.
#include "locus/pipelines/laplacian/weight_active_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "locus/error.hpp"

namespace locus {

WeightActiveSet::WeightActiveSet(int32_t nv, std::span<const int32_t> e0, std::span<const int32_t> e1,
                                 std::span<const uint8_t> fixed, const WeightActiveSetOptions& opt)
    : e0_(e0.begin(), e0.end()), e1_(e1.begin(), e1.end()), fixed_(fixed.begin(), fixed.end()), opt_(opt) {
  const size_t ne = e0.size();
  if (e1.size() != ne || fixed.size() != static_cast<size_t>(nv))
    fail(ErrorCode::BadInput, "weight active set: inconsistent sizes (edge ends, fixed flags)");
  if (opt.window < 1 || !(opt.min_rate > 0) || !(opt.fade > 0 && opt.fade <= 1) || !(opt.max_log_step > 0) ||
      !(opt.vanish_rel > 0) || opt.max_drops < 0 || opt.max_drops > 16)
    fail(ErrorCode::BadUsage, "weight active set: need window >= 1, min_rate > 0, 0 < fade <= 1, max_log_step > 0, "
                              "vanish_rel > 0, 0 <= max_drops <= 16");
  state_.assign(ne, WeightState::active);
  for (size_t e = 0; e < ne; ++e) {
    if (e0[e] < 0 || e0[e] >= nv || e1[e] < 0 || e1[e] >= nv)
      fail(ErrorCode::BadInput, "weight active set: edge " + std::to_string(e) + " is out of range");
    if (fixed[e0[e]] && fixed[e1[e]]) state_[e] = WeightState::passive;
  }
  streak_.assign(ne, 0);
  push_.assign(ne, 0);
  g_start_.assign(ne, 0.0);
  u_start_.assign(ne, 0.0);
  drops_.assign(ne, 0);
  vmax_.assign(static_cast<size_t>(nv), 0.0);
  vpush_.assign(static_cast<size_t>(nv), 0);
  vstep_.assign(static_cast<size_t>(nv), 0.0);
  rebuild_active();
}

void WeightActiveSet::rebuild_active() {
  active_.clear();
  const int32_t nv = static_cast<int32_t>(fixed_.size());
  active_degree_.assign(static_cast<size_t>(nv), 0);
  for (size_t e = 0; e < state_.size(); ++e)
    if (state_[e] == WeightState::active) {
      active_.push_back(static_cast<int32_t>(e));
      ++active_degree_[e0_[e]];
      ++active_degree_[e1_[e]];
    }
  std::vector<int32_t> parent;
  anchored_ = edges_anchor_free_vertices(e0_, e1_, fixed_,
                                         [&](size_t e) { return state_[e] == WeightState::active; }, parent);
}

bool WeightActiveSet::exempt(size_t e) const {
  return (!fixed_[e0_[e]] && active_degree_[e0_[e]] == 0) || (!fixed_[e1_[e]] && active_degree_[e1_[e]] == 0);
}

double WeightActiveSet::push_step(size_t e, double g_e) const {
  const double va = vstep_[e0_[e]], vb = vstep_[e1_[e]];
  if (va < 0 || vb < 0) return std::min(va, vb);  // an end is vanishing: its common push
  const int j = std::min(push_[e], 200);
  return std::max(g_e * std::pow(opt_.push_growth, j), -opt_.max_log_step);
}

int32_t WeightActiveSet::observe(std::span<const double> g, std::span<const double> w, std::span<double> U) {
  const int32_t nv = static_cast<int32_t>(fixed_.size());
  std::fill(vmax_.begin(), vmax_.end(), 0.0);
  double wmax = 0;
  for (int32_t e : active_) {
    vmax_[e0_[e]] = std::max(vmax_[e0_[e]], w[e]);
    vmax_[e1_[e]] = std::max(vmax_[e1_[e]], w[e]);
    wmax = std::max(wmax, w[e]);
  }
  // 1. Decay streaks; undo pushes the mesh disagrees with.
  for (int32_t e : active_) {
    const double ge = g[e];
    if (push_[e] > 0 && ge > 0.0) {  // the mesh wants it back: undo the speculative push
      if (opt_.restore_on_undo) U[e] = std::max(U[e], u_start_[e]);
      push_[e] = 0;
      streak_[e] = 0;
      ++num_revived_;
      continue;
    }
    if (!(ge < -opt_.min_rate)) {
      streak_[e] = 0;
      push_[e] = 0;
      continue;
    }
    if (streak_[e] > 0 && std::abs(ge) >= (1 - opt_.fade) * std::abs(g_start_[e])) {
      ++streak_[e];
    } else {  // a new streak starts here
      streak_[e] = 1;
      push_[e] = 0;
      g_start_[e] = ge;
      u_start_[e] = U[e];
    }
    if (drops_[e] >= opt_.max_drops) continue;
    const int64_t need = static_cast<int64_t>(opt_.window) << drops_[e];  // longer after each revival
    if (streak_[e] >= need && push_[e]++ == 0) ++num_pushes_;
  }
  // 2. Vanishing vertices: every active edge pushed. Their edges share one push.
  std::vector<int32_t> npushed(static_cast<size_t>(nv), 0);
  std::vector<double> gsum(static_cast<size_t>(nv), 0.0);
  for (int32_t e : active_)
    if (push_[e] > 0)
      for (int32_t v : {e0_[e], e1_[e]}) {
        ++npushed[v];
        gsum[v] += g[e];
      }
  for (int32_t v = 0; v < nv; ++v) {
    const bool vanishing = !fixed_[v] && active_degree_[v] > 0 && npushed[v] == active_degree_[v];
    vpush_[v] = vanishing ? vpush_[v] + 1 : 0;
    vstep_[v] = vanishing ? std::max(gsum[v] / npushed[v] * std::pow(opt_.push_growth, std::min(vpush_[v], 200)),
                                     -opt_.max_log_step)
                          : 0.0;
  }
  // 3. Drop vanished pushed weights: small next to the strongest active weight at
  // each free end that keeps its edges (only free ends move when the edge goes);
  // a vanishing end compares with the largest weight overall.
  int32_t dropped = 0;
  for (int32_t e : active_) {
    if (push_[e] == 0) continue;
    double local = HUGE_VAL;
    for (int32_t v : {e0_[e], e1_[e]})
      if (!fixed_[v]) local = std::min(local, vstep_[v] < 0 ? wmax : vmax_[v]);
    if (w[e] <= opt_.vanish_rel * local) {
      state_[e] = WeightState::dropped;
      ++drops_[e];
      push_[e] = 0;
      streak_[e] = 0;
      ++num_dropped_;
      ++dropped;
    }
  }
  if (dropped) rebuild_active();
  return dropped;
}

bool WeightActiveSet::drop(size_t e) {
  if (state_[e] != WeightState::active) return state_[e] == WeightState::dropped;
  if (drops_[e] >= opt_.max_drops) return false;
  state_[e] = WeightState::dropped;
  ++drops_[e];
  push_[e] = 0;
  streak_[e] = 0;
  ++num_dropped_;
  rebuild_active();
  return true;
}

int32_t WeightActiveSet::revive_violators(std::span<const double> g, std::span<double> U) {
  std::vector<int32_t> back;
  for (size_t e = 0; e < state_.size(); ++e)
    if (state_[e] == WeightState::dropped && g[e] > opt_.kkt_tol && !exempt(e)) back.push_back(static_cast<int32_t>(e));
  for (int32_t e : back) {
    state_[e] = WeightState::active;
    U[e] = u_start_[e];
    streak_[e] = 0;
    push_[e] = 0;
    --num_dropped_;
    ++num_revived_;
  }
  if (!back.empty()) rebuild_active();
  return static_cast<int32_t>(back.size());
}

double WeightActiveSet::max_violation(std::span<const double> g) const {
  double worst = -std::numeric_limits<double>::infinity();
  for (size_t e = 0; e < state_.size(); ++e)
    if (state_[e] == WeightState::dropped && !exempt(e)) worst = std::max(worst, g[e]);
  return worst;
}

}  // namespace locus
