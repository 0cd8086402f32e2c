// Refinement of sampled skinning weights: exact rows at rough vertices, border
// probes, growth, closing and the budgeted growth
// (pipelines/include/locus/pipelines/voronoi/skinning_refine.hpp; thesis §3.7.2).
#include "locus/pipelines/voronoi/skinning_refine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "locus/error.hpp"

namespace locus {

namespace {

// Rings around a rough vertex or a probe within which no further probe is placed.
constexpr int32_t kProbeSpacing = 2;
constexpr double kProbeJump = 1.4;
// Rings around a propagated row within which the exact rows' residuals correct it.
constexpr int32_t kCorrectRings = 2;
// Closing: share of exact neighbours that makes a vertex exact too.
constexpr double kClosingShare = 0.75;
// Closing: an exact neighbour whose row differs by more than this x miss
// (locus-bench skinning: 1.2 instead of 2 brings armadillo 4 from 0.068 to 0.065
// max |w - w_exact| and armadillo 7 from 0.062 to 0.055 at the same budget).
constexpr double kClosingJump = 1.2;
constexpr int kClosingRounds = 4;
// The budgeted growth's threshold, in units of `miss` (locus-bench skinning: 0.6
// brings camel 7 from 0.082 to 0.045 max |w - w_exact|).
constexpr double kBudgetMiss = 0.6;
// A propagated weight under this next to a row that has it 0 is 0 (locus-bench
// skinning: armadillo 7's last weight outside the natural neighbourhood's one-ring
// band, 0.0075, goes; the max |w - w_exact| moves nowhere; at 0.02 the means grow
// 1-8 %, at 0.01 0-3 %).
constexpr double kKeepZeroBelow = 0.01;

struct Refiner {
  const Adjacency& adj;
  std::span<const int32_t> owner;
  const SolveSkinRows& solve_rows;
  SkinningWeights& W;
  std::vector<uint8_t> exact;  // row exact (sample, refined or queued)
  std::vector<uint8_t> cellless;  // row an indicator for want of a cell (handle vertex, degenerate query)
  int64_t exact_rows = 0;      // samples + refined

  int32_t n() const { return static_cast<int32_t>(adj.offsets.size()) - 1; }
  bool open(int32_t u) const { return !exact[u] && owner[u] < 0; }

  double row_diff(const double* a, const double* b) const {
    double d = 0;
    for (int32_t j = 0; j < W.handles; ++j) d = std::max(d, std::abs(a[j] - b[j]));
    return d;
  }
  const double* row(int32_t v) const { return W.weight.data() + static_cast<size_t>(v) * W.handles; }

  // Growth from `front` (open vertices, sorted): solve, then queue the open
  // neighbours of every vertex whose exact row misses its propagated one by more
  // than `miss`. budget >= 0: at most that many exact rows in all; a front over it
  // keeps the neighbours of the largest misses.
  void grow(std::vector<int32_t> front, double miss, int64_t budget = -1) {
    const int32_t k = W.handles;
    for (int32_t v : front) exact[v] = 1;
    std::vector<double> rows;
    std::vector<uint8_t> indicator;
    std::vector<std::pair<double, int32_t>> next;
    while (!front.empty()) {
      solve_rows(front, rows, indicator);
      for (size_t i = 0; i < front.size(); ++i) cellless[front[i]] = indicator[i];
      W.refined += static_cast<int32_t>(front.size());
      exact_rows += static_cast<int64_t>(front.size());
      next.clear();
      for (size_t i = 0; i < front.size(); ++i) {
        double* w = W.weight.data() + static_cast<size_t>(front[i]) * k;
        const double d = row_diff(w, rows.data() + i * k);
        std::copy_n(rows.begin() + i * k, k, w);
        if (d <= miss) continue;
        for (int64_t p = adj.offsets[front[i]]; p < adj.offsets[front[i] + 1]; ++p) {
          const int32_t u = adj.neighbors[p];
          if (!open(u)) continue;
          exact[u] = 1;
          next.push_back({-d, u});
        }
      }
      if (budget >= 0 && exact_rows + static_cast<int64_t>(next.size()) > budget) {
        std::sort(next.begin(), next.end());
        const size_t keep = static_cast<size_t>(std::max<int64_t>(0, budget - exact_rows));
        for (size_t i = keep; i < next.size(); ++i) exact[next[i].second] = 0;
        next.resize(keep);
      }
      front.clear();
      for (const auto& e : next) front.push_back(e.second);
      std::sort(front.begin(), front.end());
    }
  }

  // Probes (header): open vertices on the borders of the samples' regions.
  std::vector<int32_t> border_probes(std::span<const int32_t> samples, std::span<const double> sample_rows,
                                     std::span<const int32_t> rough, double jump) const {
    const int32_t nv = n(), k = W.handles;
    std::vector<int32_t> label(nv, -1), queue;
    for (int32_t i = 0; i < static_cast<int32_t>(samples.size()); ++i) {
      label[samples[i]] = i;
      queue.push_back(samples[i]);
    }
    for (size_t h = 0; h < queue.size(); ++h)  // nearest sample in edges, breadth-first in sample order
      for (int64_t p = adj.offsets[queue[h]]; p < adj.offsets[queue[h] + 1]; ++p)
        if (label[adj.neighbors[p]] < 0) {
          label[adj.neighbors[p]] = label[queue[h]];
          queue.push_back(adj.neighbors[p]);
        }
    std::vector<std::pair<double, int32_t>> cand;
    for (int32_t v = 0; v < nv; ++v) {
      if (label[v] < 0 || !open(v)) continue;
      double best = 0;
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
        const int32_t u = adj.neighbors[p];
        if (label[u] < 0 || label[u] == label[v]) continue;
        best = std::max(best, row_diff(sample_rows.data() + static_cast<size_t>(label[u]) * k,
                                       sample_rows.data() + static_cast<size_t>(label[v]) * k));
      }
      if (best > jump) cand.push_back({-best, v});
    }
    std::sort(cand.begin(), cand.end());
    std::vector<int32_t> ring(nv, -1), probes;
    auto block = [&](int32_t s) {  // mark the vertices within kProbeSpacing edges of s
      queue.assign(1, s);
      ring[s] = 0;
      for (size_t h = 0; h < queue.size(); ++h) {
        const int32_t v = queue[h];
        if (ring[v] >= kProbeSpacing) continue;
        for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
          const int32_t u = adj.neighbors[p];
          if (ring[u] >= 0 && ring[u] <= ring[v] + 1) continue;
          ring[u] = ring[v] + 1;
          queue.push_back(u);
        }
      }
    };
    for (int32_t v : rough) block(v);
    for (const auto& c : cand)
      if (ring[c.second] < 0) {
        probes.push_back(c.second);
        block(c.second);
      }
    return probes;
  }

  // Closing candidates (header).
  std::vector<int32_t> closing(double jump) const {
    std::vector<int32_t> out;
    for (int32_t v = 0; v < n(); ++v) {
      if (!open(v)) continue;
      const int64_t deg = adj.offsets[v + 1] - adj.offsets[v];
      int64_t known = 0;
      double d = 0;
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
        const int32_t u = adj.neighbors[p];
        if (!exact[u]) continue;
        ++known;
        d = std::max(d, row_diff(row(u), row(v)));
      }
      if (d > jump || (deg > 0 && static_cast<double>(known) >= kClosingShare * static_cast<double>(deg)))
        out.push_back(v);
    }
    return out;
  }

  // The open vertices of `irregular` (ascending), as many as the budget leaves.
  std::vector<int32_t> open_within_budget(std::span<const int32_t> irregular, int64_t budget) {
    std::vector<int32_t> out;
    for (int32_t v : irregular)
      if (exact_rows + static_cast<int64_t>(out.size()) < budget && open(v)) out.push_back(v);
    return out;
  }

  // The budgeted growth's first front: open neighbours of exact rows that missed
  // their propagated row (interp) by more than `miss`, the largest misses first.
  std::vector<std::pair<double, int32_t>> missed_neighbours(std::span<const double> interp, double miss) {
    std::vector<std::pair<double, int32_t>> out;
    for (int32_t v = 0; v < n(); ++v) {
      if (!exact[v] || owner[v] >= 0) continue;
      const double d = row_diff(row(v), interp.data() + static_cast<size_t>(v) * W.handles);
      if (d <= miss) continue;
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
        const int32_t u = adj.neighbors[p];
        if (!open(u)) continue;
        exact[u] = 1;
        out.push_back({-d, u});
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  }
};

}  // namespace

void refine_sampled_rows(const Adjacency& adj, std::span<const int32_t> samples, std::span<const double> sample_rows,
                         std::span<const uint8_t> sample_indicator, std::span<const int32_t> rough,
                         std::span<const int32_t> irregular, std::span<const int32_t> owner, double miss,
                         int64_t row_budget, const SolveSkinRows& solve_rows, SkinningWeights& W) {
  const size_t nv = static_cast<size_t>(adj.offsets.size()) - 1;
  if (sample_indicator.size() != samples.size() || owner.size() != nv)
    fail(ErrorCode::BadUsage, "refine sampled rows: sizes do not match");
  Refiner R{adj, owner, solve_rows, W, std::vector<uint8_t>(nv, 0), std::vector<uint8_t>(nv, 0), 0};
  for (size_t i = 0; i < samples.size(); ++i) {
    R.exact[samples[i]] = 1;
    R.cellless[samples[i]] = sample_indicator[i];
  }
  R.exact_rows = static_cast<int64_t>(samples.size());
  const std::vector<double> interp = W.weight;  // the propagated rows, for the budgeted growth
  std::vector<int32_t> seeds = R.border_probes(samples, sample_rows, rough, kProbeJump * miss);
  for (int32_t v : rough)
    if (R.open(v)) seeds.push_back(v);
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  R.grow(seeds, miss, row_budget);
  for (int round = 0; round < kClosingRounds && R.exact_rows < row_budget; ++round) {
    std::vector<int32_t> close = R.closing(kClosingJump * miss);
    if (close.empty()) break;
    R.grow(close, miss, row_budget);
  }
  std::vector<std::pair<double, int32_t>> front = R.missed_neighbours(interp, kBudgetMiss * miss);
  const size_t keep = static_cast<size_t>(std::max<int64_t>(0, row_budget - R.exact_rows));
  for (size_t i = keep; i < front.size(); ++i) R.exact[front[i].second] = 0;
  if (front.size() > keep) front.resize(keep);
  std::vector<int32_t> first;
  for (const auto& e : front) first.push_back(e.second);
  std::sort(first.begin(), first.end());
  R.grow(first, kBudgetMiss * miss, row_budget);
  R.grow(R.open_within_budget(irregular, row_budget), kBudgetMiss * miss, row_budget);
  std::vector<uint8_t> known(R.exact), zeros(R.exact.size());
  for (int32_t v = 0; v < R.n(); ++v) {
    known[v] = known[v] || owner[v] >= 0;
    zeros[v] = owner[v] < 0 && !R.cellless[v];
  }
  correct_propagated_rows(adj, known, interp, W);
  keep_neighbour_zeros(adj, known, zeros, kKeepZeroBelow, W);
}

void keep_neighbour_zeros(const Adjacency& adj, std::span<const uint8_t> exact, std::span<const uint8_t> zero_source,
                          double below, SkinningWeights& W) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1, k = W.handles;
  if (exact.size() != static_cast<size_t>(n) || zero_source.size() != static_cast<size_t>(n) ||
      W.weight.size() != static_cast<size_t>(n) * k)
    fail(ErrorCode::BadUsage, "keep neighbour zeros: sizes do not match");
  const std::vector<double> in(W.weight);  // every row reads the rows as they came in
  std::vector<double> before(k);
  for (int32_t v = 0; v < n; ++v) {
    if (exact[v]) continue;
    double* o = W.weight.data() + static_cast<size_t>(v) * k;
    std::copy_n(o, k, before.begin());
    bool moved = false;
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
      const int32_t u = adj.neighbors[p];
      if (!zero_source[u]) continue;
      const double* w = in.data() + static_cast<size_t>(u) * k;
      for (int32_t j = 0; j < k; ++j)
        if (w[j] == 0.0 && o[j] > 0.0 && o[j] < below) {
          o[j] = 0.0;
          moved = true;
        }
    }
    if (!moved) continue;
    double sum = 0;
    for (int32_t j = 0; j < k; ++j) sum += o[j];
    if (sum > 0)
      for (int32_t j = 0; j < k; ++j) o[j] /= sum;
    else  // every weight was small: the row as it was
      std::copy(before.begin(), before.end(), o);
  }
}

void correct_propagated_rows(const Adjacency& adj, std::span<const uint8_t> exact, std::span<const double> interp,
                             SkinningWeights& W) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1, k = W.handles;
  if (exact.size() != static_cast<size_t>(n) || W.weight.size() != static_cast<size_t>(n) * k ||
      interp.size() != W.weight.size())
    fail(ErrorCode::BadUsage, "correct propagated rows: sizes do not match");
  std::vector<double> out(W.weight);
  std::vector<int32_t> ring(n, -1), queue;
  std::vector<double> lo(k), hi(k);
  for (int32_t v = 0; v < n; ++v) {
    if (exact[v]) continue;
    queue.assign(1, v);
    ring[v] = 0;
    bool any = false;
    std::fill(lo.begin(), lo.end(), std::numeric_limits<double>::infinity());
    std::fill(hi.begin(), hi.end(), -std::numeric_limits<double>::infinity());
    for (size_t h = 0; h < queue.size(); ++h) {  // breadth-first, kCorrectRings deep
      const int32_t x = queue[h];
      if (exact[x]) {
        any = true;
        for (int32_t j = 0; j < k; ++j) {
          const size_t a = static_cast<size_t>(x) * k + j;
          lo[j] = std::min(lo[j], W.weight[a] - interp[a]);
          hi[j] = std::max(hi[j], W.weight[a] - interp[a]);
        }
      }
      if (ring[x] >= kCorrectRings) continue;
      for (int64_t p = adj.offsets[x]; p < adj.offsets[x + 1]; ++p)
        if (ring[adj.neighbors[p]] < 0) {
          ring[adj.neighbors[p]] = ring[x] + 1;
          queue.push_back(adj.neighbors[p]);
        }
    }
    for (int32_t x : queue) ring[x] = -1;
    if (!any) continue;
    double* o = out.data() + static_cast<size_t>(v) * k;
    double sum = 0;
    // minmod: per weight the residual of least magnitude when all agree in sign,
    // else 0; only weights > 0 move. The side (gains or losses) that moves more
    // is scaled down to the other: the row keeps its sum, and a residual that
    // cannot land (on a weight at 0) is not handed to the others by the
    // renormalization (armadillo 4: 0.051 -> 0.048 max |w - w_exact|).
    double gain = 0, loss = 0;
    for (int32_t j = 0; j < k; ++j) {
      const double c = lo[j] > 0 ? lo[j] : (hi[j] < 0 ? hi[j] : 0.0);
      if (o[j] > 0) (c > 0 ? gain : loss) += std::max(c, -o[j]);
    }
    const double scale_gain = gain > -loss ? -loss / gain : 1.0, scale_loss = -loss > gain ? gain / -loss : 1.0;
    for (int32_t j = 0; j < k; ++j) {
      const double c = lo[j] > 0 ? lo[j] : (hi[j] < 0 ? hi[j] : 0.0);
      if (o[j] > 0) o[j] = std::max(0.0, o[j] + (c > 0 ? scale_gain : scale_loss) * c);
      sum += o[j];
    }
    if (sum > 0)
      for (int32_t j = 0; j < k; ++j) o[j] /= sum;
    else  // every weight cancelled: the propagated row
      std::copy_n(W.weight.data() + static_cast<size_t>(v) * k, k, o);
  }
  W.weight.swap(out);
}

std::vector<int32_t> skinny_corners(const Mesh& m, double max_angle_deg) {
  const int32_t n = m.num_vertices();
  const double limit = std::cos(max_angle_deg * std::numbers::pi / 180.0);
  std::vector<uint8_t> mark(n, 0);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto c = m.face(f);
    const size_t nc = c.size();
    for (size_t e = 0; e < nc; ++e) {  // the angle at corner c[e] between its two edges
      const int32_t a = c[e], b = c[(e + 1) % nc], d = c[(e + nc - 1) % nc];
      const double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], uz = m.z[b] - m.z[a];
      const double vx = m.x[d] - m.x[a], vy = m.y[d] - m.y[a], vz = m.z[d] - m.z[a];
      const double uu = ux * ux + uy * uy + uz * uz, vv = vx * vx + vy * vy + vz * vz;
      if (uu > 0 && vv > 0 && ux * vx + uy * vy + uz * vz > limit * std::sqrt(uu * vv)) mark[a] = 1;
    }
  }
  std::vector<int32_t> out;
  for (int32_t v = 0; v < n; ++v)
    if (mark[v]) out.push_back(v);
  return out;
}

}  // namespace locus
