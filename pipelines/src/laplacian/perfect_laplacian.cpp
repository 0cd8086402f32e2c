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

}  // namespace

PerfectLaplacianResult run_perfect_laplacian(const PerfectLaplacianProblem& P, const PerfectLaplacianOptions& opt,
                                             const RunContext& ctx) {
  const int32_t nv = P.nv;
  const size_t ne = P.e0.size();
  const int dims = P.dims;
  if (dims != 2 && dims != 3) fail(ErrorCode::BadUsage, "perfect Laplacian: dims must be 2 or 3");
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

  if (opt.method == PerfectLaplacianMethod::newton) {
    PerfectLaplacianResult N = run_perfect_laplacian_newton(P, opt, ctx);
    weight_statistics(opt, N);
    return N;
  }

  PerfectLaplacianResult R;
  const auto t_first = Clock::now();
  EmbeddingSystem sys(nv, P.e0, P.e1, P.fixed, opt.system);
  R.order_s = sys.order_s();
  R.analyze_s = sys.analyze_s();

  // With b = 0 the embedding does not change when all weights are scaled: the
  // steady state fixes ω only up to scale and the active edges' length ratios to
  // a common μ^-1 that need not be 1 (§2.3.3). The residual is then the log
  // ratio minus its ω²-weighted mean c (the first-order shift of the
  // normalization), so that it vanishes at the steady state instead of drifting
  // by log μ^-1 per iteration. With b != 0 the raw weights carry the scale (see
  // the header) and the residual is the plain log ratio.
  const bool scale_free = perfect_laplacian_detail::scale_free(P);
  R.scale_free = scale_free;

  // ω^(0) = 1 (or the caller's). The state is the vector U of log raw weights;
  // the system is assembled with the normalized weights ω = exp(U - C),
  // C = log ||exp U|| over the edges not dropped, and b scaled by exp(-C).
  std::vector<double> U(ne, 0.0);
  if (!P.initial_weights.empty())
    for (size_t e = 0; e < ne; ++e) {
      if (!(P.initial_weights[e] > 0.0) || !std::isfinite(P.initial_weights[e]))
        fail(ErrorCode::BadInput, "perfect Laplacian: initial weight of edge " + std::to_string(e) + " is not positive");
      U[e] = std::log(P.initial_weights[e]);
    }
  WeightActiveSet aset(nv, P.e0, P.e1, P.fixed, opt.active_set);
  std::vector<double> w(ne);
  double rhs_scale = 1.0;
  const double log_floor = std::log(opt.floor_rel);
  auto max_active_u = [&]() {
    double umax = -std::numeric_limits<double>::infinity();
    for (int32_t e : aset.active()) umax = std::max(umax, U[e]);
    return umax;
  };
  // Normalized weights from U: dropped edges exactly 0.
  auto weights_from = [&]() {
    double umax = -std::numeric_limits<double>::infinity();
    for (size_t e = 0; e < ne; ++e)
      if (aset.state(e) != WeightState::dropped) umax = std::max(umax, U[e]);
    double s = 0;
    for (size_t e = 0; e < ne; ++e)
      if (aset.state(e) != WeightState::dropped) s += std::exp(2 * (U[e] - umax));
    const double c = umax + 0.5 * std::log(s);
    for (size_t e = 0; e < ne; ++e) w[e] = aset.state(e) == WeightState::dropped ? 0.0 : std::exp(U[e] - c);
    rhs_scale = std::exp(-c);
  };
  // In the scale-free case the level of the active U is arbitrary; it is kept at
  // its initial log-sum-exp so that passive edges (not iterated) stay comparable.
  auto active_lse = [&]() {
    const double umax = max_active_u();
    double s = 0;
    for (int32_t e : aset.active()) s += std::exp(U[e] - umax);
    return umax + std::log(s);
  };
  const double lse_ref = aset.active().empty() ? 0.0 : active_lse();
  weights_from();

  auto aa = std::make_unique<AndersonAcceleration>(opt.anderson_depth, aset.active().size());
  std::vector<double> f(ne), g(ne), x, r, xn;
  double best_f = std::numeric_limits<double>::infinity();
  auto restart_acceleration = [&]() {
    aa = std::make_unique<AndersonAcceleration>(opt.anderson_depth, aset.active().size());
    best_f = std::numeric_limits<double>::infinity();
  };

  Coords V, Vprev;
  std::vector<double> later_s;
  bool have_prev = false;
  // The first iteration's time includes ordering and analysis (done above).
  auto record_time = [&](int k, Clock::time_point t_iter) {
    if (k == 1)
      R.first_iter_s = seconds_since(t_first);
    else
      later_s.push_back(seconds_since(t_iter));
  };
  for (int k = 1; k <= opt.max_iterations; ++k) {
    ctx.check_cancel();
    const auto t_iter = Clock::now();
    // Dropped weights are exact zeros; the positivity floor is needed only when
    // they leave some free vertex without a positive path to a fixed one.
    sys.set_weight_floor_rel(aset.anchored() ? 0.0 : opt.system.weight_floor_rel);
    sys.factor(w, ctx);
    sys.solve(dims, P.fixed_pos, P.b, rhs_scale, V);
    ++R.factorizations;
    R.iterations = k;

    // Convergence: the largest vertex change of this iteration against the diagonal.
    const double diag = bbox_diagonal(dims, V, static_cast<size_t>(nv));
    double change = 0;
    if (have_prev)
      for (int32_t v = 0; v < nv; ++v) {
        double s = 0;
        for (int c = 0; c < dims; ++c) s += (V[c][v] - Vprev[c][v]) * (V[c][v] - Vprev[c][v]);
        change = std::max(change, s);
      }
    change = std::sqrt(change);
    const double change_rel = diag > 0 ? change / diag : 0.0;
    if (have_prev) R.change_history.push_back(change_rel);
    R.last_change_rel = have_prev ? change_rel : 0.0;

    // The plain step of eq. 2.8 in log form is U += f, f = log(||e|| / ||ê||); g is
    // the residual (f minus the normalization shift in the scale-free case).
    double c = 0, cw = 0;
    for (size_t e = 0; e < ne; ++e) {
      double len = edge_length(dims, V, P.e0[e], P.e1[e]);
      if (!(len > 0.0)) len = 1e-300;  // collapsed edge: its weight shrinks as fast as allowed
      f[e] = std::log(len / P.target_length[e]);
    }
    if (scale_free && opt.center_residual) {
      for (int32_t e : aset.active()) {
        c += w[e] * w[e] * f[e];
        cw += w[e] * w[e];
      }
      c = cw > 0 ? c / cw : 0.0;
    }
    for (size_t e = 0; e < ne; ++e) g[e] = f[e] - c;

    const bool converged_now = have_prev && change_rel < opt.eps;
    if (converged_now && opt.drop_decaying && R.kkt_rounds < opt.max_kkt_rounds &&
        aset.revive_violators(g, U) > 0) {
      // Steady state reached with this active set, but some dropped edges would
      // grow back (KKT): they return at their pre-decay weight; iterate on.
      ++R.kkt_rounds;
      restart_acceleration();
      weights_from();
      Vprev.swap(V);
      record_time(k, t_iter);
      continue;
    }
    if (converged_now || k == opt.max_iterations) {
      R.converged = converged_now;
      record_time(k, t_iter);
      break;  // keep ω^(k): V is the equilibrium of exactly these weights
    }

    // Established decays are pushed, vanished ones dropped (weight_active_set.hpp).
    if (opt.drop_decaying && aset.observe(g, w, U) > 0) restart_acceleration();

    const auto& A = aset.active();
    const size_t na = A.size();
    x.resize(na);
    r.resize(na);
    double fnorm = 0;
    for (size_t i = 0; i < na; ++i) {
      x[i] = U[A[i]];
      r[i] = aset.pushed(A[i]) ? 0.0 : opt.relaxation * g[A[i]];  // converged as far as the acceleration is concerned
      fnorm += r[i] * r[i];
    }
    fnorm = std::sqrt(fnorm);
    if (opt.anderson_depth > 0 && fnorm > opt.anderson_restart * best_f) aa->clear();  // extrapolation made it worse
    best_f = std::min(best_f, fnorm);
    aa->step(x, r, xn);
    // Safeguard: no weight changes by more than a factor exp(max_log_step) at once.
    double big = 0;
    for (size_t i = 0; i < na; ++i) big = std::max(big, std::abs(xn[i] - x[i]));
    const double t = big > opt.max_log_step ? opt.max_log_step / big : 1.0;
    for (size_t i = 0; i < na; ++i)
      U[A[i]] = aset.pushed(A[i]) ? x[i] + aset.push_step(A[i], g[A[i]]) : x[i] + t * (xn[i] - x[i]);
    if (scale_free && na > 0) {
      const double shift = active_lse() - lse_ref;
      for (int32_t e : A) U[e] -= shift;
    }
    // Backstop: a weight below floor_rel · max has reached its limit 0 whatever its
    // history; one that may not be dropped any more is held at the floor.
    const double umax = max_active_u();
    bool dropped = false;
    const std::vector<int32_t> Acopy = A;  // drop() rebuilds the active list
    for (int32_t e : Acopy)
      if (U[e] - umax <= log_floor) {
        if (opt.drop_decaying && aset.drop(static_cast<size_t>(e)))
          dropped = true;
        else
          U[e] = umax + log_floor;
      }
    if (dropped) restart_acceleration();
    weights_from();
    Vprev.swap(V);
    have_prev = true;
    record_time(k, t_iter);
    ctx.report(static_cast<double>(k) / opt.max_iterations, "perfect Laplacian iterations");
  }
  // The weights V is in equilibrium with (ω of the last solve).
  R.pos = std::move(V);
  R.weights = std::move(w);
  R.rhs_scale = rhs_scale;
  R.iter_s = perfect_laplacian_detail::median(later_s);
  R.revived = aset.num_revived();
  R.kkt_violation = aset.num_dropped() > 0 ? aset.max_violation(g) : 0.0;
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
  const std::vector<double>* x[3] = {&m.x, &m.y, &m.z};
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
  R.e0 = inc.edges.e0;
  R.e1 = inc.edges.e1;
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
  Coords input{m.x, m.y, m.z};
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

  if (planar) {
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
    bool convex = true;
    for (size_t i = 0; i < nb && convex; ++i) {
      const int32_t a = L[(i + nb - 1) % nb], b = L[i], c = L[(i + 1) % nb];
      const double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], wx = m.x[c] - m.x[b], wy = m.y[c] - m.y[b];
      const double cr = orient * (ux * wy - uy * wx);
      // Weakly convex: collinear boundary vertices (cr == 0 up to rounding) are allowed.
      if (cr < -1e-12 * std::hypot(ux, uy) * std::hypot(wx, wy)) convex = false;
    }
    for (int32_t v : L) P.fixed[v] = 1;
    if (!convex) {
      // Tutte/Floater need a convex boundary: place the loop on a circle of the
      // same perimeter around its centroid, spaced by arc length, same orientation.
      R.boundary_on_circle = true;
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
        P.fixed_pos[0][L[i]] = cx + r * std::cos(ang);
        P.fixed_pos[1][L[i]] = cy + r * std::sin(ang);
      }
    }
    // b = 0: planar interior vertices have zero mean curvature (eq. 2.4).
  } else {
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

  R.run = run_perfect_laplacian(P, opt.iteration, ctx);
  if (dims == 2) R.run.pos[2] = m.z;  // the plane the mesh lies in
  R.align_scale = align_similarity(dims, R.run.pos, input, R.aligned);
  if (dims == 2) R.aligned[2] = m.z;
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
  R.total_s = seconds_since(t0);
  return R;
}

}  // namespace locus
