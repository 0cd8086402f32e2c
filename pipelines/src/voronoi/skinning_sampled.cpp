// Sampled skinning weights: greedy sample cover and Shepard propagation
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
  for (int32_t v = 0; v < n; ++v)
    if (!covered[v]) add(v);
  return samples;
}

namespace {

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
  int32_t v;
  double phi;
};

}  // namespace

Propagation propagate_samples(const Mesh& m, const Adjacency& adj, std::span<const int32_t> samples,
                              std::span<const double> rows, int32_t k, std::span<double> out, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(samples.size());
  if (rows.size() != static_cast<size_t>(ns) * k || out.size() != static_cast<size_t>(n) * k)
    fail(ErrorCode::BadUsage, "propagate samples: sizes do not match");
  Propagation P;
  double dmax = 0;  // the cover radius in length units
  Dijkstra all;
  all.run(m, adj, samples, std::numeric_limits<double>::infinity(), [&](int32_t, double d) { dmax = std::max(dmax, d); });
  P.radius = 2 * dmax;
  std::vector<double> den(n, 0.0);
  std::fill(out.begin(), out.end(), 0.0);
  if (dmax > 0) {
    const double rho = P.radius;
    tbb::enumerable_thread_specific<Dijkstra> balls;
    constexpr int32_t kChunk = 256;  // balls held at once: memory stays O(chunk * ball)
    std::vector<std::vector<BallEntry>> ball(kChunk);
    const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
    for (int32_t first = 0; first < ns; first += kChunk) {
      ctx.check_cancel();
      const int32_t count = std::min(kChunk, ns - first);
      run_with_threads(std::max(1, threads), [&] {
        tbb::parallel_for(0, count, [&](int32_t i) {
          std::vector<BallEntry>& b = ball[i];
          b.clear();
          const int32_t s = samples[first + i];
          balls.local().run(m, adj, {&s, 1}, rho, [&](int32_t v, double d) {
            if (v == s || d >= rho) return;
            const double dd = std::max(d, 1e-12 * rho);
            const double phi = (rho - dd) / (rho * dd);
            b.push_back({v, phi * phi});
          });
        });
      });
      for (int32_t i = 0; i < count; ++i) {  // sample order: deterministic sums
        const double* w = rows.data() + static_cast<size_t>(first + i) * k;
        P.ball_entries += static_cast<int64_t>(ball[i].size());
        for (const BallEntry& e : ball[i]) {
          double* o = out.data() + static_cast<size_t>(e.v) * k;
          for (int32_t j = 0; j < k; ++j) o[j] += e.phi * w[j];
          den[e.v] += e.phi;
        }
      }
    }
  }
  for (int32_t i = 0; i < ns; ++i) {  // samples keep their rows (the weight is infinite at d = 0)
    std::copy_n(rows.begin() + static_cast<size_t>(i) * k, k, out.begin() + static_cast<size_t>(samples[i]) * k);
    den[samples[i]] = 1.0;
  }
  for (int32_t v = 0; v < n; ++v) {
    double* o = out.data() + static_cast<size_t>(v) * k;
    if (!(den[v] > 0)) fail(ErrorCode::Numerical, "propagate samples: vertex " + std::to_string(v) + " sees no sample");
    double sum = 0;
    for (int32_t j = 0; j < k; ++j) sum += o[j];
    for (int32_t j = 0; j < k; ++j) o[j] /= sum;  // a convex combination of unit-sum rows: renormalized to rounding
  }
  return P;
}

}  // namespace locus
