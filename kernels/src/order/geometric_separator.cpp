// Plane-cut vertex separators (kernels/include/locus/kernels/order/geometric_separator.hpp).
#include "locus/kernels/order/geometric_separator.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace locus {

namespace {

// The best split of the vertices ranked along direction d: side[v] = 1 for the
// first k in rank order, with k inside the balance window and cutting the
// fewest edges (ties: the k nearest the middle). Returns the cut size.
int64_t best_split_along(const AdjacencyGraph& g, std::span<const double> x, std::span<const double> y,
                         std::span<const double> z, const Eigen::Vector3d& d, double window,
                         HostVector<int32_t>& rank, HostVector<double>& proj, HostVector<int8_t>& side) {
  const int32_t m = g.n();
  proj.resize(m);
  for (int32_t v = 0; v < m; ++v) proj[v] = d.x() * x[v] + d.y() * y[v] + d.z() * z[v];
  rank.resize(m);
  std::iota(rank.begin(), rank.end(), 0);
  const auto less = [&proj](int32_t a, int32_t b) { return proj[a] < proj[b] || (proj[a] == proj[b] && a < b); };
  const int32_t half = m / 2;
  const int32_t lo = std::clamp(static_cast<int32_t>(std::floor(m * (0.5 - window))), 1, half);
  const int32_t hi = std::clamp(static_cast<int32_t>(std::ceil(m * (0.5 + window))), half, m - 1);
  std::nth_element(rank.begin(), rank.begin() + lo, rank.end(), less);
  std::nth_element(rank.begin() + lo, rank.begin() + hi, rank.end(), less);
  std::sort(rank.begin() + lo, rank.begin() + hi, less);
  side.assign(m, 0);
  for (int32_t k = 0; k < lo; ++k) side[rank[k]] = 1;
  int64_t cut = 0;
  for (int32_t k = 0; k < lo; ++k) {
    const int32_t v = rank[k];
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) cut += side[g.adj[p]] == 0;
  }
  int64_t best_cut = cut;
  int32_t best_k = lo;
  for (int32_t k = lo; k < hi; ++k) {  // move rank[k] to side 1: the split becomes k + 1
    const int32_t v = rank[k];
    int32_t in = 0;
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) in += side[g.adj[p]];
    cut += (g.degree(v) - in) - in;
    side[v] = 1;
    const int32_t kk = k + 1;
    if (cut < best_cut || (cut == best_cut && std::abs(kk - half) < std::abs(best_k - half))) {
      best_cut = cut;
      best_k = kk;
    }
  }
  for (int32_t k = best_k; k < hi; ++k) side[rank[k]] = 0;
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
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int32_t v = 0; v < m; ++v) {
    const Eigen::Vector3d q = Eigen::Vector3d(x[v], y[v], z[v]) - c;
    cov += q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  HostVector<int32_t> rank;
  HostVector<double> proj;
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
    const int64_t cut = best_split_along(g, x, y, z, d, window, rank, proj, side);
    if (best < 0 || cut < best) {
      best = cut;
      best_side.swap(side);
    }
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
