// Level-structure vertex separators (kernels/include/locus/kernels/order/level_separator.hpp).
#include "locus/kernels/order/level_separator.hpp"

#include <algorithm>
#include <cstdlib>
#include <utility>

namespace locus {

namespace {

// Breadth-first levels from root (level[v] = -1: not reached); `order` gets
// the vertices in visiting order. Returns the number of levels.
int32_t bfs_levels(const AdjacencyGraph& g, int32_t root, HostVector<int32_t>& level, HostVector<int32_t>& order) {
  level.assign(static_cast<size_t>(g.n()), -1);
  order.clear();
  order.push_back(root);
  level[root] = 0;
  for (size_t h = 0; h < order.size(); ++h) {
    const int32_t v = order[h];
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (const int32_t w = g.adj[p]; level[w] < 0) {
        level[w] = level[v] + 1;
        order.push_back(w);
      }
  }
  return level[order.back()] + 1;
}

}  // namespace

bool level_separator(const AdjacencyGraph& g, std::span<const int32_t> vwgt, HostVector<int8_t>& part) {
  const int32_t n = g.n();
  if (n < 3) return false;
  HostVector<int32_t> level, order, try_level, try_order;
  // A pseudo-peripheral root: restart from a least-connected vertex of the
  // last level while that makes the structure deeper (long and thin level
  // structures have small levels). level/order keep the deepest so far.
  int32_t depth = bfs_levels(g, 0, level, order);
  if (static_cast<int32_t>(order.size()) != n) return false;  // not connected
  for (int round = 0; round < 4; ++round) {
    int32_t c = order.back();
    for (auto it = order.rbegin(); it != order.rend() && level[*it] == depth - 1; ++it)
      if (g.degree(*it) < g.degree(c) || (g.degree(*it) == g.degree(c) && *it < c)) c = *it;
    const int32_t d = bfs_levels(g, c, try_level, try_order);
    if (d <= depth) break;
    std::swap(level, try_level);
    std::swap(order, try_order);
    depth = d;
  }
  if (depth < 3) return false;
  HostVector<int64_t> w(static_cast<size_t>(depth), 0);
  for (int32_t v = 0; v < n; ++v) w[level[v]] += vwgt.empty() ? 1 : vwgt[v];
  int64_t total = 0;
  for (const int64_t x : w) total += x;
  // The lightest level among those that leave sides within 1.3x of even,
  // else the best balanced one.
  int32_t best = -1;
  bool best_ok = false;
  int64_t before = w[0], best_w = 0, best_diff = 0;
  for (int32_t l = 1; l + 1 < depth; before += w[l], ++l) {
    const int64_t s0 = before, s1 = total - before - w[l];
    const int64_t diff = std::abs(s0 - s1);
    const bool ok = 20 * std::max(s0, s1) <= 13 * (s0 + s1);
    const bool better = best < 0 || (ok && !best_ok) ||
                        (ok == best_ok && (ok ? w[l] < best_w || (w[l] == best_w && diff < best_diff) : diff < best_diff));
    if (better) {
      best = l;
      best_ok = ok;
      best_w = w[l];
      best_diff = diff;
    }
  }
  part.resize(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) part[v] = static_cast<int8_t>(level[v] < best ? 0 : level[v] == best ? 2 : 1);
  return true;
}

}  // namespace locus
