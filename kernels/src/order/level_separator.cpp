// Level-structure separators (kernels/include/locus/kernels/order/level_separator.hpp).
#include "locus/kernels/order/level_separator.hpp"

#include <algorithm>
#include <numeric>

namespace locus {

namespace {

// Breadth-first search from s over the vertices with comp[v] == c; order
// receives the visit order, level[v] the distance. Returns the number of levels.
int32_t bfs(const AdjacencyGraph& g, int32_t s, std::vector<int32_t>& level, std::vector<int32_t>& order) {
  order.clear();
  order.push_back(s);
  level[s] = 0;
  for (size_t q = 0; q < order.size(); ++q) {
    const int32_t v = order[q];
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p)
      if (const int32_t w = g.adj[p]; level[w] < 0) { level[w] = level[v] + 1; order.push_back(w); }
  }
  return level[order.back()] + 1;
}

// Cuts the component reached from s (its vertices get 0, 1 or 2 in part).
void cut_component(const AdjacencyGraph& g, int32_t s, const LevelSeparatorOptions& opt, std::vector<int32_t>& level,
                   std::vector<int32_t>& order, std::vector<int8_t>& part) {
  int32_t nlev = 0;
  for (int sweep = 0; sweep < std::max(1, opt.sweeps); ++sweep) {
    for (const int32_t v : order) level[v] = -1;
    if (sweep == 0) level[s] = -1;
    nlev = bfs(g, s, level, order);
    if (sweep + 1 < opt.sweeps) {
      // Farthest vertex of least degree (ties: lowest index): the next start.
      int32_t best = order.back();
      for (auto it = order.rbegin(); it != order.rend() && level[*it] == nlev - 1; ++it)
        if (g.degree(*it) < g.degree(best) || (g.degree(*it) == g.degree(best) && *it < best)) best = *it;
      s = best;
    }
  }
  std::vector<int32_t> count(static_cast<size_t>(nlev), 0);
  for (const int32_t v : order) ++count[level[v]];
  const int64_t size = static_cast<int64_t>(order.size());
  const int64_t lo = static_cast<int64_t>((0.5 - opt.balance_window) * static_cast<double>(size));
  const int64_t hi = static_cast<int64_t>((0.5 + opt.balance_window) * static_cast<double>(size));
  // Level L as separator: side 0 = levels < L. Smallest level whose side 0
  // lies in the window (else the level holding the median vertex).
  int32_t cut = -1;
  int64_t below = 0, median_level = 0;
  for (int32_t L = 0; L < nlev; ++L) {
    if (below <= size / 2 && below + count[L] > size / 2) median_level = L;
    if (below >= lo && below <= hi && (cut < 0 || count[L] < count[cut])) cut = L;
    below += count[L];
  }
  if (cut < 0) cut = static_cast<int32_t>(median_level);
  for (const int32_t v : order) part[v] = level[v] < cut ? 0 : level[v] == cut ? 2 : 1;
}

}  // namespace

void level_separator(const AdjacencyGraph& g, const LevelSeparatorOptions& opt, std::vector<int8_t>& part) {
  const int32_t m = g.n();
  part.assign(m, 0);
  if (m < 2) return;
  std::vector<int32_t> level(static_cast<size_t>(m), -1), order;
  order.reserve(m);
  // Components, in order of their lowest vertex.
  std::vector<int32_t> comp_start, comp_size;
  for (int32_t v = 0; v < m; ++v)
    if (level[v] < 0) {
      comp_start.push_back(v);
      bfs(g, v, level, order);
      comp_size.push_back(static_cast<int32_t>(order.size()));
    }
  std::fill(level.begin(), level.end(), -1);
  order.clear();
  const size_t nc = comp_start.size();
  const size_t big = static_cast<size_t>(std::max_element(comp_size.begin(), comp_size.end()) - comp_size.begin());
  std::vector<int32_t> comp_order;
  const auto assign_whole = [&](size_t c, int8_t side) {
    comp_order.clear();
    bfs(g, comp_start[c], level, comp_order);
    for (const int32_t v : comp_order) part[v] = side;
  };
  if (nc > 1 && 2 * static_cast<int64_t>(comp_size[big]) <= static_cast<int64_t>(m) * (1.0 + 2 * opt.balance_window)) {
    // Whole components, largest first, each to the lighter side: no separator at all.
    std::vector<size_t> by_size(nc);
    std::iota(by_size.begin(), by_size.end(), size_t{0});
    std::stable_sort(by_size.begin(), by_size.end(), [&](size_t a, size_t b) { return comp_size[a] > comp_size[b]; });
    int64_t w[2] = {0, 0};
    for (const size_t c : by_size) {
      const int8_t side = w[0] <= w[1] ? 0 : 1;
      assign_whole(c, side);
      w[side] += comp_size[c];
    }
    return;
  }
  // Cut the largest component; the others join the lighter side.
  order.clear();
  cut_component(g, comp_start[big], opt, level, order, part);
  int64_t w[2] = {0, 0};
  for (int32_t v = 0; v < m; ++v)
    if (level[v] >= 0 && part[v] < 2) ++w[part[v]];
  for (size_t c = 0; c < nc; ++c)
    if (c != big) {
      const int8_t side = w[0] <= w[1] ? 0 : 1;
      assign_whole(c, side);
      w[side] += comp_size[c];
    }
  refine_vertex_separator(g, part, opt.refinement);
}

}  // namespace locus
