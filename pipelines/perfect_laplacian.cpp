// Perfect Laplacians for polygon meshes: Algorithm 1 (thesis §2.3, eqs. 2.4-2.11).
// See perfect_laplacian.hpp for the loop, the right-hand-side scale and the
// treatment of geometrically decaying weights.
#include "pipelines/perfect_laplacian.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "kernels/mesh_operators.hpp"
#include "kernels/mesh_topology.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median_of(std::vector<double> v) {
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

double edge_length(int dims, const Coords& p, int32_t a, int32_t b) {
  double s = 0;
  for (int k = 0; k < dims; ++k) {
    const double d = p[k][b] - p[k][a];
    s += d * d;
  }
  return std::sqrt(s);
}

// Divides w by its 2-norm and returns the norm (0 if w is all zero).
double normalize(std::vector<double>& w) {
  double s = 0;
  for (double x : w) s += x * x;
  const double n = std::sqrt(s);
  if (n > 0)
    for (double& x : w) x /= n;
  return n;
}

// Anderson acceleration (type II, Walker & Ni 2011) of a fixed-point iteration
// u <- u + f(u): keeps the last `depth` differences of u and f and extrapolates
// u_next = u + f - (ΔU + ΔF) γ with γ = argmin ||f - ΔF γ|| (small normal
// equations, Tikhonov-regularized). depth 0 is the plain iteration.
class Anderson {
 public:
  Anderson(int depth, size_t n) : depth_(depth), n_(n) {}
  void clear() {
    dU_.clear();
    dF_.clear();
    have_last_ = false;
  }
  void step(const std::vector<double>& u, const std::vector<double>& f, std::vector<double>& out) {
    if (have_last_) {
      std::vector<double> du(n_), df(n_);
      for (size_t i = 0; i < n_; ++i) {
        du[i] = u[i] - last_u_[i];
        df[i] = f[i] - last_f_[i];
      }
      dU_.push_back(std::move(du));
      dF_.push_back(std::move(df));
      if (static_cast<int>(dU_.size()) > depth_) {
        dU_.erase(dU_.begin());
        dF_.erase(dF_.begin());
      }
    }
    last_u_ = u;
    last_f_ = f;
    have_last_ = true;
    const int m = static_cast<int>(dF_.size());
    out.resize(n_);
    for (size_t i = 0; i < n_; ++i) out[i] = u[i] + f[i];
    if (m == 0) return;
    // Normal equations (ΔF^T ΔF + λ I) γ = ΔF^T f, solved by Gaussian elimination.
    std::vector<double> G(static_cast<size_t>(m * m)), r(static_cast<size_t>(m));
    double trace = 0;
    for (int a = 0; a < m; ++a) {
      for (int b = 0; b <= a; ++b) {
        double s = 0;
        for (size_t i = 0; i < n_; ++i) s += dF_[a][i] * dF_[b][i];
        G[a * m + b] = G[b * m + a] = s;
      }
      trace += G[a * m + a];
      double s = 0;
      for (size_t i = 0; i < n_; ++i) s += dF_[a][i] * f[i];
      r[a] = s;
    }
    if (!(trace > 0)) return;
    for (int a = 0; a < m; ++a) G[a * m + a] += 1e-10 * trace;
    for (int c = 0; c < m; ++c) {  // SPD: no pivoting needed
      for (int a = c + 1; a < m; ++a) {
        const double l = G[a * m + c] / G[c * m + c];
        for (int b = c; b < m; ++b) G[a * m + b] -= l * G[c * m + b];
        r[a] -= l * r[c];
      }
    }
    std::vector<double> g(static_cast<size_t>(m));
    for (int a = m - 1; a >= 0; --a) {
      double s = r[a];
      for (int b = a + 1; b < m; ++b) s -= G[a * m + b] * g[b];
      g[a] = s / G[a * m + a];
    }
    for (int a = 0; a < m; ++a)
      for (size_t i = 0; i < n_; ++i) out[i] -= g[a] * (dU_[a][i] + dF_[a][i]);
  }

 private:
  int depth_;
  size_t n_;
  std::vector<std::vector<double>> dU_, dF_;
  std::vector<double> last_u_, last_f_;
  bool have_last_ = false;
};

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

  PerfectLaplacianResult R;
  const auto t_first = Clock::now();
  EmbeddingSystem sys(nv, P.e0, P.e1, P.fixed, opt.system);
  R.order_s = sys.order_s();
  R.analyze_s = sys.analyze_s();

  // ω^(0) = 1 (or the caller's). The state is the vector U of log raw weights;
  // the system is assembled with the normalized weights ω = exp(U - c),
  // c = log ||exp U||, and b scaled by rhs_scale = exp(-c) (see the header).
  std::vector<double> U(ne, 0.0);
  if (!P.initial_weights.empty())
    for (size_t e = 0; e < ne; ++e) {
      if (!(P.initial_weights[e] > 0.0) || !std::isfinite(P.initial_weights[e]))
        fail(ErrorCode::BadInput, "perfect Laplacian: initial weight of edge " + std::to_string(e) + " is not positive");
      U[e] = std::log(P.initial_weights[e]);
    }
  std::vector<double> w(ne);
  double rhs_scale = 1.0;
  const double log_floor = std::log(opt.floor_rel);
  // Normalized weights from U; entries at or below the floor become exactly 0.
  auto weights_from = [&](const std::vector<double>& u) {
    const double umax = ne ? *std::max_element(u.begin(), u.end()) : 0.0;
    double s = 0;
    for (size_t e = 0; e < ne; ++e) s += std::exp(2 * (u[e] - umax));
    const double c = umax + 0.5 * std::log(s);
    for (size_t e = 0; e < ne; ++e) w[e] = u[e] - umax <= log_floor ? 0.0 : std::exp(u[e] - c);
    rhs_scale = std::exp(-c);
  };
  weights_from(U);

  Anderson aa(opt.anderson_depth, ne);
  std::vector<double> f(ne), Unext(ne);
  double best_f = std::numeric_limits<double>::infinity();

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
    sys.factor(w, ctx);
    sys.solve(dims, P.fixed_pos, P.b, rhs_scale, V);
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
    if ((have_prev && change_rel < opt.eps) || k == opt.max_iterations) {
      R.converged = have_prev && change_rel < opt.eps;
      record_time(k, t_iter);
      break;  // keep ω^(k): V is the equilibrium of exactly these weights
    }

    // The plain step of eq. 2.8 in log form: U += log(||e|| / ||ê||) (the
    // normalization is a shift of U, applied in weights_from). Weights at the floor
    // that still want to shrink have reached their limit 0: their step is 0.
    const double umax = *std::max_element(U.begin(), U.end());
    double fnorm = 0;
    for (size_t e = 0; e < ne; ++e) {
      double len = edge_length(dims, V, P.e0[e], P.e1[e]);
      if (!(len > 0.0)) len = 1e-300;  // collapsed edge: shrink its weight as far as allowed
      f[e] = std::log(len / P.target_length[e]);
      if (U[e] - umax <= log_floor && f[e] < 0) f[e] = 0.0;
      fnorm += f[e] * f[e];
    }
    fnorm = std::sqrt(fnorm);
    if (opt.anderson_depth > 0) {
      // Restart the extrapolation when it made things clearly worse.
      if (fnorm > opt.anderson_restart * best_f) aa.clear();
      best_f = std::min(best_f, fnorm);
      aa.step(U, f, Unext);
      // Safeguard: no weight changes by more than a factor exp(max_log_step) at once.
      double big = 0;
      for (size_t e = 0; e < ne; ++e) big = std::max(big, std::abs(Unext[e] - U[e]));
      const double t = big > opt.max_log_step ? opt.max_log_step / big : 1.0;
      for (size_t e = 0; e < ne; ++e) Unext[e] = U[e] + t * (Unext[e] - U[e]);
    } else {
      for (size_t e = 0; e < ne; ++e) Unext[e] = U[e] + f[e];
    }
    // Below the floor nothing changes any more: hold there (exactly 0 in ω).
    const double umax_next = *std::max_element(Unext.begin(), Unext.end());
    for (size_t e = 0; e < ne; ++e) Unext[e] = std::max(Unext[e], umax_next + log_floor - 1.0);
    U.swap(Unext);
    weights_from(U);
    Vprev.swap(V);
    have_prev = true;
    record_time(k, t_iter);
    ctx.report(static_cast<double>(k) / opt.max_iterations, "perfect Laplacian iterations");
  }
  // The weights V is in equilibrium with (ω of the last solve).
  R.pos = std::move(V);
  R.weights = std::move(w);
  R.rhs_scale = rhs_scale;
  R.iter_s = median_of(later_s);
  double wmax = 0;
  R.min_weight = ne ? R.weights[0] : 0.0;
  R.min_positive_weight = 0;
  for (double x : R.weights) {
    wmax = std::max(wmax, x);
    R.min_weight = std::min(R.min_weight, x);
    if (x > 0 && (R.min_positive_weight == 0 || x < R.min_positive_weight)) R.min_positive_weight = x;
  }
  for (double x : R.weights) {
    if (x <= opt.zero_weight_rel * wmax) ++R.zero_weights;
    if (x == 0.0) ++R.at_floor;
  }
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
