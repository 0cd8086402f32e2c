// Plane-cut vertex separators (kernels/include/locus/kernels/order/geometric_separator.hpp).
#include "locus/kernels/order/geometric_separator.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace locus {

namespace {

// Split points are bin boundaries: the projections are binned uniformly, and
// the range is narrowed around the balance window until the window spans
// enough boundaries. A sort of the window (every split point) was over half
// of the nested dissection's CPU at 104k (perf); with the FM passes after the
// cut (nested_dissection.cpp) the bins fill no more (docs/ordering.md).
constexpr int32_t kMaxBins = 2048;
constexpr int kNarrowRounds = 4;

// Scratch of best_split_along, kept across directions.
struct SplitSpace {
  HostVector<double> proj;
  HostVector<int32_t> bin, below;
  HostVector<int64_t> diff;
};

// Bins the projections sp.proj[0..m) in [a, b] (their range, b > a): bins
// 1..bins cover a range uniformly, 0 is below it, bins + 1 above; the range
// is narrowed around the balance window [lo, hi] until the window spans
// enough boundaries. Leaves sp.bin and sp.below[k] = the vertices in bins
// < k (side 1 of boundary k); returns the window's boundaries {kl, kh},
// below[k] in [lo, hi] (kh < kl: none).
std::pair<int32_t, int32_t> bin_window(int32_t m, double a, double b, int32_t lo, int32_t hi, int32_t bins,
                                       SplitSpace& sp) {
  const int32_t enough = bins / 8;
  sp.bin.resize(m);
  sp.below.resize(static_cast<size_t>(bins) + 3);
  int32_t kl = 0, kh = 0;
  for (int round = 0;; ++round) {
    const double scale = bins / (b - a) * (1 - 1e-12);  // b itself in the last bin
    std::fill(sp.below.begin(), sp.below.end(), 0);
    for (int32_t v = 0; v < m; ++v) {
      const double t = (sp.proj[v] - a) * scale;
      const int32_t k = t < 0 ? 0 : t >= bins ? bins + 1 : 1 + static_cast<int32_t>(t);
      sp.bin[v] = k;
      ++sp.below[k + 1];
    }
    for (int32_t k = 1; k < bins + 3; ++k) sp.below[k] += sp.below[k - 1];
    kl = 0;
    while (sp.below[kl] < lo) ++kl;  // below[bins + 2] = m > lo
    kh = kl - 1;
    while (kh + 1 < bins + 3 && sp.below[kh + 1] <= hi) ++kh;
    if (kh - kl + 1 >= enough || round + 1 == kNarrowRounds || kl < 2 || kh > bins) break;
    // Narrow to the bins holding the window's ends: bin kl - 1 (the lo-th
    // vertex) to bin kh (the one after the hi-th).
    const double na = a + (kl - 2) / scale, nb = a + kh / scale;
    if (!(nb > na)) break;  // no finer range in doubles: keep these bins
    a = na;
    b = nb;
  }
  return {kl, kh};
}

// The best split of the vertices along direction d: side[v] = 1 for the
// vertices below a threshold, their count inside the balance window, the
// threshold the bin boundary cutting the fewest edges (ties: the count
// nearest the middle). Edges with neither end inside the window's bins are
// not counted (they would cross every candidate). Returns the cut size, or
// -1 when no boundary lies in the window (all projections equal).
int64_t best_split_along(const AdjacencyGraph& g, std::span<const double> x, std::span<const double> y,
                         std::span<const double> z, const Eigen::Vector3d& d, double window, SplitSpace& sp,
                         HostVector<int8_t>& side) {
  const int32_t m = g.n();
  sp.proj.resize(m);
  double a = std::numeric_limits<double>::infinity(), b = -a;
  for (int32_t v = 0; v < m; ++v) {
    const double q = d.x() * x[v] + d.y() * y[v] + d.z() * z[v];
    sp.proj[v] = q;
    a = std::min(a, q);
    b = std::max(b, q);
  }
  if (!(b > a)) return -1;
  const int32_t half = m / 2;
  const int32_t lo = std::clamp(static_cast<int32_t>(std::floor(m * (0.5 - window))), 1, half);
  const int32_t hi = std::clamp(static_cast<int32_t>(std::ceil(m * (0.5 + window))), half, m - 1);
  // Fewer bins on small graphs, where the passes over the bins would
  // outweigh the ones over the vertices.
  const int32_t bins = std::clamp(m / 2, 64, kMaxBins);
  const auto [kl, kh] = bin_window(m, a, b, lo, hi, bins, sp);
  if (kl > kh) return -1;
  // cut(k) = edges with min bin < k <= max bin, by differences over k.
  sp.diff.assign(static_cast<size_t>(bins) + 3, 0);
  const int32_t first_bin = kl - 1, last_bin = kh;  // bins whose vertices border a candidate
  for (int32_t v = 0; v < m; ++v) {
    const int32_t bv = sp.bin[v];
    if (bv < first_bin || bv > last_bin) continue;
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) {
      const int32_t w = g.adj[p];
      const int32_t bw = sp.bin[w];
      const bool w_inside = bw >= first_bin && bw <= last_bin;
      if (bw == bv || (w_inside && w < v)) continue;  // each edge once
      ++sp.diff[std::min(bv, bw) + 1];
      --sp.diff[std::max(bv, bw) + 1];
    }
  }
  int64_t cut = 0, best_cut = -1;
  int32_t best_k = kl;
  for (int32_t k = 0; k <= kh; ++k) {
    cut += sp.diff[k];
    if (k < kl) continue;
    const int64_t off = std::abs(static_cast<int64_t>(sp.below[k]) - half);
    if (best_cut < 0 || cut < best_cut ||
        (cut == best_cut && off < std::abs(static_cast<int64_t>(sp.below[best_k]) - half))) {
      best_cut = cut;
      best_k = k;
    }
  }
  side.resize(m);
  for (int32_t v = 0; v < m; ++v) side[v] = sp.bin[v] < best_k ? 1 : 0;
  return best_cut;
}

}  // namespace

void geometric_separator(const AdjacencyGraph& g, std::span<const double> x, std::span<const double> y,
                         std::span<const double> z, const GeometricSeparatorOptions& opt, HostVector<int8_t>& part) {
  const int32_t m = g.n();
  part.assign(m, 0);
  if (m < 2) return;
  // Principal axes of the points' inertia, about their centroid.
  Eigen::Vector3d c(0, 0, 0);
  for (int32_t v = 0; v < m; ++v) c += Eigen::Vector3d(x[v], y[v], z[v]);
  c /= m;
  // Six scalar sums: the matrix is symmetric.
  double sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  for (int32_t v = 0; v < m; ++v) {
    const double qx = x[v] - c.x(), qy = y[v] - c.y(), qz = z[v] - c.z();
    sxx += qx * qx;
    sxy += qx * qy;
    sxz += qx * qz;
    syy += qy * qy;
    syz += qy * qz;
    szz += qz * qz;
  }
  Eigen::Matrix3d cov;
  cov << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  SplitSpace sp;
  HostVector<int8_t> side, best_side;
  int64_t best = -1;
  // The three principal axes, then the four diagonals between them: a cut
  // across a limb or a neck is often oblique to all three axes.
  const Eigen::Matrix3d& V = eig.eigenvectors();
  std::vector<Eigen::Vector3d> dirs{V.col(2), V.col(1), V.col(0)};  // largest spread first: it wins ties
  if (opt.diagonals)
    for (double s1 : {1.0, -1.0})
      for (double s2 : {1.0, -1.0}) dirs.push_back((V.col(2) + s1 * V.col(1) + s2 * V.col(0)).normalized());
  const double window = opt.balance_window;
  for (const Eigen::Vector3d& d : dirs) {
    const int64_t cut = best_split_along(g, x, y, z, d, window, sp, side);
    if (cut >= 0 && (best < 0 || cut < best)) {
      best = cut;
      best_side.swap(side);
    }
  }
  if (best < 0) {
    // Every direction degenerate (the points coincide): halves by index.
    best_side.resize(m);
    for (int32_t v = 0; v < m; ++v) best_side[v] = v < m / 2 ? 1 : 0;
  }
  part.assign(best_side.begin(), best_side.end());
  minimum_cover_separator(g, part);
}

void minimum_cover_separator(const AdjacencyGraph& g, HostVector<int8_t>& part) {
  const int32_t m = g.n();
  // Boundary of side 0 (the left set of the bipartite cut graph).
  HostVector<int32_t> left;
  for (int32_t v = 0; v < m; ++v) {
    if (part[v] != 0) continue;
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (part[g.adj[p]] == 1) { left.push_back(v); break; }
  }
  if (left.empty()) return;
  // Maximum matching by augmenting paths (Kuhn), greedy start; iterative DFS.
  HostVector<int32_t> mate(m, -1), seen(m, -1), stack_v, stack_p;
  for (int32_t u : left)
    for (int32_t p = g.xadj[u]; p < g.xadj[u + 1]; ++p) {
      const int32_t w = g.adj[p];
      if (part[w] == 1 && mate[w] < 0) { mate[w] = u; mate[u] = w; break; }
    }
  for (size_t r = 0; r < left.size(); ++r) {
    const int32_t root = left[r];
    if (mate[root] >= 0) continue;
    stack_v.assign(1, root);
    stack_p.assign(1, g.xadj[root]);
    seen[root] = static_cast<int32_t>(r);
    bool found = false;
    while (!stack_v.empty() && !found) {
      const int32_t u = stack_v.back();
      int32_t& p = stack_p.back();
      if (p == g.xadj[u + 1]) { stack_v.pop_back(); stack_p.pop_back(); continue; }
      const int32_t w = g.adj[p++];
      if (part[w] != 1 || seen[w] == static_cast<int32_t>(r)) continue;
      seen[w] = static_cast<int32_t>(r);
      if (mate[w] < 0) {
        // Augment along the stack: u_k - w_k pairs.
        int32_t free_w = w;
        for (size_t k = stack_v.size(); k-- > 0;) {
          const int32_t uk = stack_v[k];
          const int32_t next_w = mate[uk];
          mate[uk] = free_w;
          mate[free_w] = uk;
          free_w = next_w;
        }
        found = true;
      } else {
        const int32_t u2 = mate[w];
        if (seen[u2] == static_cast<int32_t>(r)) continue;
        seen[u2] = static_cast<int32_t>(r);
        stack_v.push_back(u2);
        stack_p.push_back(g.xadj[u2]);
      }
    }
  }
  // König: Z = vertices reachable from unmatched left vertices by alternating
  // paths; the cover is (left \ Z) + (right & Z).
  HostVector<int8_t> inz(m, 0);
  HostVector<int32_t> queue;
  for (int32_t u : left)
    if (mate[u] < 0) { inz[u] = 1; queue.push_back(u); }
  for (size_t q = 0; q < queue.size(); ++q) {
    const int32_t u = queue[q];  // a left vertex
    for (int32_t p = g.xadj[u]; p < g.xadj[u + 1]; ++p) {
      const int32_t w = g.adj[p];
      if (part[w] != 1 || inz[w]) continue;
      inz[w] = 1;
      const int32_t u2 = mate[w];  // w is matched, else u's path would augment
      if (u2 >= 0 && !inz[u2]) { inz[u2] = 1; queue.push_back(u2); }
    }
  }
  for (int32_t u : left)
    if (!inz[u]) part[u] = 2;
  for (int32_t v = 0; v < m; ++v)
    if (part[v] == 1 && inz[v]) part[v] = 2;
}

}  // namespace locus
