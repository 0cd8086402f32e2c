// Sampled skinning weights: greedy sample cover and moving-least-squares propagation
// (pipelines/include/locus/pipelines/voronoi/skinning_sampled.hpp; thesis §3.7.2).
#include "locus/pipelines/voronoi/skinning_sampled.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"

namespace locus {

std::vector<int32_t> cover_samples(const Adjacency& adj, std::span<const int32_t> first, int32_t rings) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1;
  if (rings < 0) fail(ErrorCode::BadUsage, "cover samples: rings must be >= 0");
  std::vector<uint8_t> covered(n, 0), is_sample(n, 0);
  std::vector<int32_t> stamp(n, -1), frontier, next, samples;
  auto add = [&](int32_t s) {
    if (is_sample[s]) return;
    is_sample[s] = 1;
    const int32_t id = static_cast<int32_t>(samples.size());
    samples.push_back(s);
    covered[s] = 1;
    stamp[s] = id;
    frontier.assign(1, s);
    for (int32_t ring = 0; ring < rings && !frontier.empty(); ++ring) {  // breadth-first, `rings` deep
      next.clear();
      for (int32_t v : frontier)
        for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
          const int32_t w = adj.neighbors[p];
          if (stamp[w] == id) continue;
          stamp[w] = id;
          covered[w] = 1;
          next.push_back(w);
        }
      frontier.swap(next);
    }
  };
  for (int32_t v : first) {
    if (v < 0 || v >= n) fail(ErrorCode::BadUsage, "cover samples: vertex " + std::to_string(v) + " out of range");
    add(v);
  }
  for (int32_t v = 0; v < n; ++v)  // a vertex without neighbours is in no face: no cell, no sample
    if (!covered[v] && adj.offsets[v + 1] > adj.offsets[v]) add(v);
  return samples;
}

namespace {

// Stencil radius and the radius within which a sample's zero is kept, in units
// of the cover radius (the largest distance from a vertex to its nearest sample),
// and the largest interpolated weight such a zero sets to 0 (bench: locus-bench
// skinning; a larger radius or threshold shrinks the supports further: at 0.03
// the armadillo's hand region lost exact weights of 0.05-0.06 of another handle,
// at 0.015 or 0.01 more weights stay outside the natural neighbourhoods' band).
constexpr double kRadiusFactor = 2.5;
constexpr double kZeroFactor = 1.5;
constexpr double kZeroBelow = 0.02;
// An interpolated weight below this times the row's largest is 0: the exact weights next to a handle hold
// scattered tiny values (1e-6..1e-4 on armadillo) of far handles whose cells the
// vertex's cell barely touches; interpolating them spreads a tail onto vertices
// whose whole one-ring has the weight exactly 0 (outside the natural neighbourhood).
constexpr double kDropBelow = 1e-3;
// The samples whose miss of the stencil's linear fit marks a vertex as rough:
// those within this many cover radii, the ones that dominate its MLS value
// (locus-bench skinning: 1.0 refines ~3x as many vertices on armadillo, 1.5 ~9x,
// for max |w - w_exact| 0.088 and 0.083 against 0.095).
constexpr double kNearFactor = 0.7;

double edge_length(const Mesh& m, int32_t a, int32_t b) {
  const double dx = m.x[a] - m.x[b], dy = m.y[a] - m.y[b], dz = m.z[a] - m.z[b];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Dijkstra on edge lengths from seeds (at distance 0), keeping vertices within
// `radius`; calls visit(v, d) as each settles. dist: n entries, +inf on entry and exit.
struct Dijkstra {
  std::vector<double> dist;
  std::vector<int32_t> touched;
  using Entry = std::pair<double, int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;

  template <class Visit>
  void run(const Mesh& m, const Adjacency& adj, std::span<const int32_t> seeds, double radius, Visit&& visit) {
    dist.resize(m.num_vertices(), std::numeric_limits<double>::infinity());
    for (int32_t s : seeds) {
      if (dist[s] == 0) continue;
      dist[s] = 0;
      touched.push_back(s);
      heap.push({0.0, s});
    }
    while (!heap.empty()) {
      const auto [d, v] = heap.top();
      heap.pop();
      if (d > dist[v]) continue;
      visit(v, d);
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
        const int32_t w = adj.neighbors[p];
        const double dw = d + edge_length(m, v, w);
        if (dw < dist[w] && dw <= radius) {
          if (dist[w] == std::numeric_limits<double>::infinity()) touched.push_back(w);
          dist[w] = dw;
          heap.push({dw, w});
        }
      }
    }
    for (int32_t v : touched) dist[v] = std::numeric_limits<double>::infinity();
    touched.clear();
  }
};

struct BallEntry {
  int32_t v;  // a vertex within the stencil radius of a sample
  double d;
};

struct StencilEntry {
  int32_t sample;  // index into samples
  double d;        // geodesic (Dijkstra) distance from the vertex
};

// Moving least squares with a linear basis (1, (x - x_v) / rho) and the
// Franke-Little weights: coefficients c_s with sum c_s = 1 and sum c_s (x_s - x_v)
// = 0 (linear precision), so smooth weights are reproduced to second order where
// Shepard's average (the fallback when the 4 x 4 system is singular) is only
// first order. The ridge on the linear terms keeps the system regular where the
// samples lie on a plane (the surface's normal direction is unresolved).
void mls_coefficients(const Mesh& m, int32_t v, std::span<const int32_t> samples, std::span<const StencilEntry> st,
                      double rho, std::vector<double>& c) {
  const size_t ns = st.size();
  c.assign(ns, 0.0);
  double phi_sum = 0;
  double A[4][4] = {};
  for (size_t i = 0; i < ns; ++i) {
    const double d = std::max(st[i].d, 1e-12 * rho);
    const double f = (rho - d) / (rho * d);
    const double phi = f * f;
    c[i] = phi;
    phi_sum += phi;
    const int32_t s = samples[st[i].sample];
    const double p[4] = {1, (m.x[s] - m.x[v]) / rho, (m.y[s] - m.y[v]) / rho, (m.z[s] - m.z[v]) / rho};
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) A[a][b] += phi * p[a] * p[b];
  }
  for (size_t i = 0; i < ns; ++i) c[i] /= phi_sum;  // Shepard, the fallback
  if (ns < 4) return;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) A[a][b] /= phi_sum;
  for (int a = 1; a < 4; ++a) A[a][a] += 1e-3;
  // Cholesky of the symmetric 4 x 4 system; e1^T A^{-1} gives the coefficients.
  double L[4][4] = {};
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b <= a; ++b) {
      double x = A[a][b];
      for (int q = 0; q < b; ++q) x -= L[a][q] * L[b][q];
      if (a == b) {
        if (!(x > 1e-14)) return;
        L[a][a] = std::sqrt(x);
      } else {
        L[a][b] = x / L[b][b];
      }
    }
  }
  double g[4] = {1, 0, 0, 0}, y[4], z[4];  // A z = e1
  for (int a = 0; a < 4; ++a) {
    y[a] = g[a];
    for (int q = 0; q < a; ++q) y[a] -= L[a][q] * y[q];
    y[a] /= L[a][a];
  }
  for (int a = 3; a >= 0; --a) {
    z[a] = y[a];
    for (int q = a + 1; q < 4; ++q) z[a] -= L[q][a] * z[q];
    z[a] /= L[a][a];
  }
  for (size_t i = 0; i < ns; ++i) {
    const int32_t s = samples[st[i].sample];
    const double p[4] = {1, (m.x[s] - m.x[v]) / rho, (m.y[s] - m.y[v]) / rho, (m.z[s] - m.z[v]) / rho};
    c[i] *= z[0] * p[0] + z[1] * p[1] + z[2] * p[2] + z[3] * p[3];
  }
}

// The stencil's weighted least-squares linear fits (Franke-Little weights, the
// ridge of mls_coefficients; the fit whose value at v the MLS combination is), one
// per weight, and their largest miss at a sample within `near` of v. A smooth
// weight misses by its curvature over the stencil only; a larger miss means the
// exact weights jump between these samples, where no interpolant follows them.
double fit_miss(const Mesh& m, int32_t v, std::span<const int32_t> samples, std::span<const StencilEntry> st,
                double rho, std::span<const double> rows, int32_t k, double near, std::vector<double>& g) {
  const size_t ns = st.size();
  double A[4][4] = {}, phi_sum = 0;
  g.assign(4 * static_cast<size_t>(k), 0.0);
  auto basis = [&](size_t i, double* p) {
    const int32_t s = samples[st[i].sample];
    p[0] = 1;
    p[1] = (m.x[s] - m.x[v]) / rho;
    p[2] = (m.y[s] - m.y[v]) / rho;
    p[3] = (m.z[s] - m.z[v]) / rho;
  };
  for (size_t i = 0; i < ns; ++i) {
    const double d = std::max(st[i].d, 1e-12 * rho);
    const double f = (rho - d) / (rho * d);
    const double phi = f * f;
    phi_sum += phi;
    double p[4];
    basis(i, p);
    const double* w = rows.data() + static_cast<size_t>(st[i].sample) * k;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) A[a][b] += phi * p[a] * p[b];
      for (int32_t j = 0; j < k; ++j) g[a * static_cast<size_t>(k) + j] += phi * p[a] * w[j];
    }
  }
  if (!(phi_sum > 0)) return 0;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) A[a][b] /= phi_sum;
  for (double& x : g) x /= phi_sum;
  for (int a = 1; a < 4; ++a) A[a][a] += 1e-3;
  double L[4][4] = {};
  bool ok = ns >= 4;
  for (int a = 0; a < 4 && ok; ++a)
    for (int b = 0; b <= a && ok; ++b) {
      double x = A[a][b];
      for (int q = 0; q < b; ++q) x -= L[a][q] * L[b][q];
      if (a == b) {
        ok = x > 1e-14;
        if (ok) L[a][a] = std::sqrt(x);
      } else {
        L[a][b] = x / L[b][b];
      }
    }
  for (int32_t j = 0; j < k; ++j) {  // coefficients of weight j into g[0..3][j]
    double z[4];
    for (int a = 0; a < 4; ++a) z[a] = g[a * static_cast<size_t>(k) + j];
    if (!ok) {  // Shepard: the weighted mean
      z[1] = z[2] = z[3] = 0;
    } else {
      for (int a = 0; a < 4; ++a) {
        for (int q = 0; q < a; ++q) z[a] -= L[a][q] * z[q];
        z[a] /= L[a][a];
      }
      for (int a = 3; a >= 0; --a) {
        for (int q = a + 1; q < 4; ++q) z[a] -= L[q][a] * z[q];
        z[a] /= L[a][a];
      }
    }
    for (int a = 0; a < 4; ++a) g[a * static_cast<size_t>(k) + j] = z[a];
  }
  double miss = 0;
  for (size_t i = 0; i < ns; ++i) {
    if (st[i].d > near) continue;
    double p[4];
    basis(i, p);
    const double* w = rows.data() + static_cast<size_t>(st[i].sample) * k;
    for (int32_t j = 0; j < k; ++j) {
      double fit = 0;
      for (int a = 0; a < 4; ++a) fit += g[a * static_cast<size_t>(k) + j] * p[a];
      miss = std::max(miss, std::abs(w[j] - fit));
    }
  }
  return miss;
}

// One vertex's row: the MLS combination of its stencil's rows, a weight set to 0
// where a stencil sample within zero_radius has it 0 (the natural neighbourhood
// is never widened past the samples' zeros) or where the combination is
// below kDropBelow times the row's largest (negative included), then
// renormalized to sum 1.
void combine_row(std::span<const StencilEntry> st, std::span<const double> c, std::span<const double> rows,
                 std::span<const uint8_t> indicator, int32_t k, double zero_radius, double* o) {
  std::fill(o, o + k, 0.0);
  for (size_t i = 0; i < st.size(); ++i) {
    const double* w = rows.data() + static_cast<size_t>(st[i].sample) * k;
    for (int32_t j = 0; j < k; ++j) o[j] += c[i] * w[j];
  }
  for (size_t i = 0; i < st.size(); ++i) {
    if (st[i].d > zero_radius || (!indicator.empty() && indicator[st[i].sample])) continue;
    const double* w = rows.data() + static_cast<size_t>(st[i].sample) * k;
    for (int32_t j = 0; j < k; ++j)
      if (w[j] == 0.0 && o[j] < kZeroBelow) o[j] = 0.0;
  }
  double top = 0;
  for (int32_t j = 0; j < k; ++j) top = std::max(top, o[j]);
  double sum = 0;
  for (int32_t j = 0; j < k; ++j) {
    if (!(o[j] > 0 && o[j] >= kDropBelow * top)) o[j] = 0.0;
    sum += o[j];
  }
  if (!(sum > 0)) {  // every weight cancelled: the nearest sample's row
    size_t best = 0;
    for (size_t i = 1; i < st.size(); ++i)
      if (st[i].d < st[best].d) best = i;
    std::copy_n(rows.data() + static_cast<size_t>(st[best].sample) * k, k, o);
    return;
  }
  for (int32_t j = 0; j < k; ++j) o[j] /= sum;
}

}  // namespace

Propagation propagate_samples(const Mesh& m, const Adjacency& adj, std::span<const int32_t> samples,
                              std::span<const double> rows, std::span<const uint8_t> indicator, int32_t k,
                              std::span<double> out, const RunContext& ctx, double refine_miss) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(samples.size());
  if (rows.size() != static_cast<size_t>(ns) * k || out.size() != static_cast<size_t>(n) * k)
    fail(ErrorCode::BadUsage, "propagate samples: sizes do not match");
  if (!indicator.empty() && indicator.size() != static_cast<size_t>(ns))
    fail(ErrorCode::BadUsage, "propagate samples: one indicator flag per sample");
  if (ns == 0) fail(ErrorCode::BadUsage, "propagate samples: no samples");
  Propagation P;
  double dmax = 0;  // the cover radius in length units
  Dijkstra all;
  all.run(m, adj, samples, std::numeric_limits<double>::infinity(), [&](int32_t, double d) { dmax = std::max(dmax, d); });
  P.radius = kRadiusFactor * dmax;
  std::fill(out.begin(), out.end(), 0.0);
  std::vector<uint8_t> is_sample(n, 0);
  for (int32_t i = 0; i < ns; ++i) {  // samples keep their rows
    std::copy_n(rows.begin() + static_cast<size_t>(i) * k, k, out.begin() + static_cast<size_t>(samples[i]) * k);
    is_sample[samples[i]] = 1;
  }
  // A vertex in no face (no neighbours) has no weights: NaN, the outside convention.
  auto in_no_face = [&](int32_t v) { return adj.offsets[v + 1] == adj.offsets[v]; };
  for (int32_t v = 0; v < n; ++v)
    if (!is_sample[v] && in_no_face(v))
      std::fill_n(out.begin() + static_cast<size_t>(v) * k, k, std::numeric_limits<double>::quiet_NaN());
  if (!(dmax > 0)) return P;
  const double rho = P.radius;
  // Per-sample balls (parallel), gathered per vertex in sample order: deterministic.
  std::vector<std::vector<BallEntry>> ball(ns);
  tbb::enumerable_thread_specific<Dijkstra> balls;
  const int threads = std::max(1, ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency());
  run_with_threads(threads, [&] {
    tbb::parallel_for(0, ns, [&](int32_t i) {
      const int32_t s = samples[i];
      balls.local().run(m, adj, {&s, 1}, rho, [&](int32_t v, double d) {
        if (!is_sample[v] && d < rho) ball[i].push_back({v, d});
      });
    });
  });
  ctx.check_cancel();
  std::vector<int64_t> off(static_cast<size_t>(n) + 1, 0);
  for (int32_t i = 0; i < ns; ++i)
    for (const BallEntry& e : ball[i]) ++off[e.v + 1];
  for (int32_t v = 0; v < n; ++v) off[v + 1] += off[v];
  std::vector<StencilEntry> st(off[n]);
  {
    std::vector<int64_t> fill(off.begin(), off.end() - 1);
    for (int32_t i = 0; i < ns; ++i) {
      for (const BallEntry& e : ball[i]) st[fill[e.v]++] = {i, e.d};
      std::vector<BallEntry>().swap(ball[i]);
    }
  }
  P.ball_entries = off[n];
  for (int32_t v = 0; v < n; ++v)
    if (!is_sample[v] && off[v + 1] == off[v] && !in_no_face(v))
      fail(ErrorCode::Numerical, "propagate samples: vertex " + std::to_string(v) + " sees no sample");
  tbb::enumerable_thread_specific<std::vector<double>> coef, fit;
  std::vector<uint8_t> rough(refine_miss > 0 ? n : 0, 0);
  run_with_threads(threads, [&] {
    tbb::parallel_for(0, n, [&](int32_t v) {
      if (is_sample[v] || in_no_face(v)) return;
      const std::span<const StencilEntry> sv(st.data() + off[v], static_cast<size_t>(off[v + 1] - off[v]));
      std::vector<double>& c = coef.local();
      mls_coefficients(m, v, samples, sv, rho, c);
      combine_row(sv, c, rows, indicator, k, kZeroFactor * dmax, out.data() + static_cast<size_t>(v) * k);
      if (refine_miss > 0)
        rough[v] = fit_miss(m, v, samples, sv, rho, rows, k, kNearFactor * dmax, fit.local()) > refine_miss;
    });
  });
  for (int32_t v = 0; v < static_cast<int32_t>(rough.size()); ++v)
    if (rough[v]) P.rough.push_back(v);
  return P;
}

}  // namespace locus
