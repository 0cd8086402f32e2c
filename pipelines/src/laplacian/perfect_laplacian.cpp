// Perfect Laplacians for polygon meshes: Algorithm 1 (thesis §2.3, eqs. 2.4-2.11).
// See perfect_laplacian.hpp for the loop, the right-hand-side scale and the
// treatment of geometrically decaying weights.
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
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

}  // namespace perfect_laplacian_detail

namespace {

using perfect_laplacian_detail::bbox_diagonal;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double edge_length(int dims, const Coords& p, int32_t a, int32_t b) {
  double s = 0;
  for (int k = 0; k < dims; ++k) {
    const double d = p[k][b] - p[k][a];
    s += d * d;
  }
  return std::sqrt(s);
}

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

double align_similarity(int dims, const Coords& p, const Coords& q, Coords& out) {
  const size_t n = p[0].size();
  double cp[3] = {0, 0, 0}, cq[3] = {0, 0, 0};
  for (int k = 0; k < dims; ++k) {
    for (size_t i = 0; i < n; ++i) {
      cp[k] += p[k][i];
      cq[k] += q[k][i];
    }
    if (n) {
      cp[k] /= static_cast<double>(n);
      cq[k] /= static_cast<double>(n);
    }
  }
  double num = 0, den = 0;
  for (int k = 0; k < dims; ++k)
    for (size_t i = 0; i < n; ++i) {
      num += (p[k][i] - cp[k]) * (q[k][i] - cq[k]);
      den += (p[k][i] - cp[k]) * (p[k][i] - cp[k]);
    }
  const double s = den > 0 ? num / den : 1.0;
  for (int k = 0; k < dims; ++k) {
    out[k].resize(n);
    for (size_t i = 0; i < n; ++i) out[k][i] = s * (p[k][i] - cp[k]) + cq[k];
  }
  return s;
}

Coords integrated_mean_curvature_normal(const Mesh& m) {
  Mesh tri;
  const Mesh* t = &m;
  if (!m.is_triangle_mesh()) {
    tri.x = m.x;
    tri.y = m.y;
    tri.z = m.z;
    tri.source = m.source;
    for (int32_t f = 0; f < m.num_faces(); ++f) {
      const auto fv = m.face(f);
      for (size_t c = 1; c + 1 < fv.size(); ++c) tri.add_triangle(fv[0], fv[c], fv[c + 1]);
    }
    t = &tri;
  }
  CscMatrix L;
  try {
    L = cotan_laplacian(*t);
  } catch (const Error& err) {
    fail(err.code(), std::string("mean-curvature normals (cotan Laplacian of the fan triangulation of the faces): ") +
                         err.what());
  }
  const int32_t nv = m.num_vertices();
  const HostVector<double>* x[3] = {&m.x, &m.y, &m.z};
  Coords b;
  for (int k = 0; k < 3; ++k) {
    b[k].assign(static_cast<size_t>(nv), 0.0);
    // Differences, so that each edge adds exactly opposite amounts: Σ_i b_i = 0.
    for (int32_t j = 0; j < nv; ++j)
      for (int64_t q = L.colptr[j] + 1; q < L.colptr[j + 1]; ++q) {
        const int32_t i = L.rowind[q];
        const double d = L.values[q] * ((*x[k])[j] - (*x[k])[i]);
        b[k][i] += d;
        b[k][j] -= d;
      }
  }
  return b;
}

namespace {

using Loops = std::vector<std::vector<int32_t>>;

// Weakly convex loop in the plane (orient = +1 counter-clockwise, -1 clockwise):
// collinear boundary vertices (cross product 0 up to rounding) are allowed.
bool weakly_convex(const Mesh& m, const std::vector<int32_t>& L, double orient) {
  const size_t nb = L.size();
  bool convex = true;
  for (size_t i = 0; i < nb && convex; ++i) {
    const int32_t a = L[(i + nb - 1) % nb], b = L[i], c = L[(i + 1) % nb];
    const double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], wx = m.x[c] - m.x[b], wy = m.y[c] - m.y[b];
    const double cr = orient * (ux * wy - uy * wx);
    if (cr < -1e-12 * std::hypot(ux, uy) * std::hypot(wx, wy)) convex = false;
  }
  return convex;
}

// Tutte/Floater need a convex boundary: place the loop on a circle of the
// same perimeter around its centroid, spaced by arc length, same orientation.
void place_loop_on_circle(const Mesh& m, const std::vector<int32_t>& L, double orient, Coords& pos) {
  const size_t nb = L.size();
  double cx = 0, cy = 0, per = 0;
  std::vector<double> arc(nb + 1, 0.0);
  for (size_t i = 0; i < nb; ++i) {
    cx += m.x[L[i]];
    cy += m.y[L[i]];
    const int32_t a = L[i], b = L[(i + 1) % nb];
    per += std::hypot(m.x[b] - m.x[a], m.y[b] - m.y[a]);
    arc[i + 1] = per;
  }
  cx /= static_cast<double>(nb);
  cy /= static_cast<double>(nb);
  const double r = per / (2 * std::numbers::pi);
  const double a0 = std::atan2(m.y[L[0]] - cy, m.x[L[0]] - cx);
  for (size_t i = 0; i < nb; ++i) {
    const double ang = a0 + orient * 2 * std::numbers::pi * arc[i] / per;
    pos[0][L[i]] = cx + r * std::cos(ang);
    pos[1][L[i]] = cy + r * std::sin(ang);
  }
}

// Planar mode (§2.3.1): the one boundary loop is held, on a circle when it is
// not convex. b = 0: planar interior vertices have zero mean curvature (eq. 2.4).
void constrain_planar(const Mesh& m, const Loops& loops, PerfectLaplacianProblem& P, MeshPerfectLaplacianResult& R) {
  if (loops.size() != 1)
    fail(ErrorCode::BadInput, mesh_name(m) + ": planar mode needs exactly one boundary loop (a disk); the mesh has " +
                                  std::to_string(loops.size()));
  const auto& L = loops[0];
  const size_t nb = L.size();
  double area2 = 0;
  for (size_t i = 0; i < nb; ++i) {
    const int32_t a = L[i], b = L[(i + 1) % nb];
    area2 += m.x[a] * m.y[b] - m.x[b] * m.y[a];
  }
  if (!(std::abs(area2) > 0.0))
    fail(ErrorCode::BadInput, mesh_name(m) + ": the boundary loop encloses no area in the plane");
  const double orient = area2 > 0 ? 1.0 : -1.0;
  const bool convex = weakly_convex(m, L, orient);
  for (int32_t v : L) P.fixed[v] = 1;
  if (!convex) {
    R.boundary_on_circle = true;
    place_loop_on_circle(m, L, orient, P.fixed_pos);
  }
}

// In space (§2.3.2): every boundary loop is held, a closed component is pinned
// at its lowest-numbered vertex, and b is the mean-curvature normal (eq. 2.10).
void constrain_space(const Mesh& m, const Loops& loops, PerfectLaplacianProblem& P, MeshPerfectLaplacianResult& R) {
  const int32_t nv = m.num_vertices();
  for (const auto& L : loops)
    for (int32_t v : L) P.fixed[v] = 1;
  std::vector<int32_t> comp;
  const int32_t nc = connected_components(m, comp);
  std::vector<uint8_t> comp_fixed(static_cast<size_t>(std::max(nc, 0)), 0);
  for (int32_t v = 0; v < nv; ++v)
    if (P.fixed[v] && comp[v] >= 0) comp_fixed[comp[v]] = 1;
  for (int32_t v = 0; v < nv; ++v)  // lowest-numbered vertex of a closed component
    if (comp[v] >= 0 && !comp_fixed[comp[v]]) {
      comp_fixed[comp[v]] = 1;
      P.fixed[v] = 1;
      ++R.pinned;
    }
  const auto tb = Clock::now();
  P.b = integrated_mean_curvature_normal(m);
  R.rhs_s = seconds_since(tb);
}

// Displacement of the aligned result from the input, relative to the input's diagonal.
void measure_displacement(int dims, const Coords& input, int32_t nv, MeshPerfectLaplacianResult& R) {
  double sum = 0, mx = 0;
  for (int32_t v = 0; v < nv; ++v) {
    double s = 0;
    for (int k = 0; k < dims; ++k) s += (R.aligned[k][v] - input[k][v]) * (R.aligned[k][v] - input[k][v]);
    const double dv = std::sqrt(s);
    sum += dv;
    mx = std::max(mx, dv);
  }
  const double diag = R.bbox_diagonal > 0 ? R.bbox_diagonal : 1.0;
  R.max_displacement_rel = mx / diag;
  R.mean_displacement_rel = sum / (static_cast<double>(nv) * diag);
}

}  // namespace

MeshPerfectLaplacianResult perfect_laplacian(const Mesh& m, const MeshPerfectLaplacianOptions& opt,
                                             const RunContext& ctx) {
  const auto t0 = Clock::now();
  MeshRequirements req;
  req.triangles = false;
  // Only the edge graph and the boundary vertices matter: non-manifold vertices
  // (several fans, common in real polygon meshes) are fine, so are such edges.
  req.manifold = false;
  req.no_degenerate_faces = false;  // the Laplacian only needs nonzero edge lengths (checked below)
  req.no_unreferenced_vertices = true;
  check_requirements(m, req);
  const int32_t nv = m.num_vertices();
  if (nv == 0 || m.num_faces() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": empty mesh");

  MeshPerfectLaplacianResult R;
  const EdgeIncidence inc = edge_incidence(m);
  R.e0.assign(inc.edges.e0.begin(), inc.edges.e0.end());
  R.e1.assign(inc.edges.e1.begin(), inc.edges.e1.end());
  const size_t ne = R.e0.size();
  const auto loops = boundary_loops(m, inc);
  R.boundary_loops = static_cast<int32_t>(loops.size());

  const auto [zlo, zhi] = std::minmax_element(m.z.begin(), m.z.end());
  const bool planar = opt.planar || *zlo == *zhi;
  R.mode = planar ? "planar" : "space";
  const int dims = planar ? 2 : 3;

  PerfectLaplacianProblem P;
  P.nv = nv;
  P.dims = dims;
  P.e0 = R.e0;
  P.e1 = R.e1;
  Coords input{std::vector<double>(m.x), std::vector<double>(m.y), std::vector<double>(m.z)};
  R.bbox_diagonal = bbox_diagonal(dims, input, static_cast<size_t>(nv));
  P.target_length.resize(ne);
  for (size_t e = 0; e < ne; ++e) {
    P.target_length[e] = edge_length(dims, input, P.e0[e], P.e1[e]);
    if (!(P.target_length[e] > 0.0))
      fail(ErrorCode::BadInput, mesh_name(m) + ": edge (" + std::to_string(P.e0[e]) + ", " + std::to_string(P.e1[e]) +
                                    ") has zero length" + (planar ? " in the plane" : "") +
                                    "; Algorithm 1 needs positive edge lengths");
  }
  P.fixed.assign(static_cast<size_t>(nv), 0);
  P.fixed_pos = input;
  if (planar)
    constrain_planar(m, loops, P, R);
  else
    constrain_space(m, loops, P, R);

  R.run = run_perfect_laplacian(P, opt.iteration, ctx);
  if (dims == 2) R.run.pos[2].assign(m.z.begin(), m.z.end());  // the plane the mesh lies in
  R.align_scale = align_similarity(dims, R.run.pos, input, R.aligned);
  if (dims == 2) R.aligned[2].assign(m.z.begin(), m.z.end());
  measure_displacement(dims, input, nv, R);
  R.total_s = seconds_since(t0);
  return R;
}

}  // namespace locus
