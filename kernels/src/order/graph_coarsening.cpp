// Shared coarsening (kernels/include/locus/kernels/order/graph_coarsening.hpp).
#include "locus/kernels/order/graph_coarsening.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "locus/core/host_allocator.hpp"

namespace locus {

namespace {

// A weighted CSR graph: one round of matching needs the edge multiplicities.
struct Weighted {
  HostVector<int32_t> xadj, adj, wgt;
  int32_t n() const { return static_cast<int32_t>(xadj.size()) - 1; }
};

// A fixed, scattered visiting order: k -> (k * stride + offset) mod n with
// stride coprime to n (a full cycle), stride near n / golden ratio so that
// consecutive visits land far apart. No sort, no library shuffle.
HostVector<int32_t> visit_order(int32_t n, uint64_t seed) {
  HostVector<int32_t> order(static_cast<size_t>(n));
  if (n == 0) return order;
  uint64_t stride = static_cast<uint64_t>(0.6180339887 * n) | 1;
  while (std::gcd(stride, static_cast<uint64_t>(n)) != 1) stride += 2;
  uint64_t v = seed % static_cast<uint64_t>(n);
  for (int32_t k = 0; k < n; ++k) {
    order[k] = static_cast<int32_t>(v);
    v += stride;
    if (v >= static_cast<uint64_t>(n)) v -= static_cast<uint64_t>(n);
  }
  return order;
}

// One round of heavy-edge matching: map[v] in [0, returned count).
int32_t match(const Weighted& g, uint64_t seed, HostVector<int32_t>& map) {
  const int32_t n = g.n();
  HostVector<int32_t> mate(static_cast<size_t>(n), -1);
  for (const int32_t v : visit_order(n, seed)) {
    if (mate[v] >= 0) continue;
    int32_t best = v, best_w = 0, best_d = 0;
    for (int32_t p = g.xadj[v]; p < g.xadj[v + 1]; ++p) {
      const int32_t w = g.adj[p];
      if (mate[w] >= 0 || w == v) continue;
      const int32_t dw = g.xadj[w + 1] - g.xadj[w];
      if (best == v || g.wgt[p] > best_w || (g.wgt[p] == best_w && (dw < best_d || (dw == best_d && w < best)))) {
        best = w;
        best_w = g.wgt[p];
        best_d = dw;
      }
    }
    mate[v] = best;
    mate[best] = v;
  }
  map.assign(static_cast<size_t>(n), -1);
  int32_t nc = 0;
  for (int32_t v = 0; v < n; ++v)
    if (map[v] < 0) { map[v] = nc; map[mate[v]] = nc; ++nc; }
  return nc;
}

// Coarse rows per block of the contraction below: blocks are built in
// parallel, each row depending on its coarse vertex only, so the result is
// the same for any thread count (and equal to one sequential pass).
constexpr int32_t kContractBlock = 4096;

// The rows of (xadj, adj) contracted along map[v] in [0, nc): coarse
// neighbors in order of first appearance (members ascending, each one's
// list in order), self loops dropped; with wgt, (*wgt)[q] = the sum of
// weight(p) over the fine edges p behind coarse edge q.
template <class Weight>
void contract_rows(std::span<const int32_t> xadj, std::span<const int32_t> adj, std::span<const int32_t> map,
                   int32_t nc, Weight weight, HostVector<int32_t>& hx, HostVector<int32_t>& hadj,
                   HostVector<int32_t>* wgt) {
  const int32_t n = static_cast<int32_t>(xadj.size()) - 1;
  HostVector<int32_t> start(static_cast<size_t>(nc) + 1, 0), members(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) ++start[map[v] + 1];
  for (int32_t c = 0; c < nc; ++c) start[c + 1] += start[c];
  {
    HostVector<int32_t> pos(start.begin(), start.end() - 1);
    for (int32_t v = 0; v < n; ++v) members[pos[map[v]]++] = v;
  }
  struct Block {
    HostVector<int32_t> adj, wgt;
  };
  struct Scratch {
    HostVector<int32_t> row, slot;  // row[d] == c: d is in row c already, at slot[d]
  };
  const int32_t nb = (nc + kContractBlock - 1) / kContractBlock;
  std::vector<Block> blocks(static_cast<size_t>(nb));
  hx.assign(static_cast<size_t>(nc) + 1, 0);
  tbb::enumerable_thread_specific<Scratch> scratch;
  const auto build = [&](int32_t b) {
    Scratch& s = scratch.local();
    if (s.row.empty()) {
      s.row.assign(static_cast<size_t>(nc), -1);
      s.slot.resize(static_cast<size_t>(nc));
    }
    Block& out = blocks[b];
    const int32_t c_end = std::min(nc, (b + 1) * kContractBlock);
    for (int32_t c = b * kContractBlock; c < c_end; ++c) {
      const size_t row_start = out.adj.size();
      for (int32_t q = start[c]; q < start[c + 1]; ++q) {
        const int32_t v = members[q];
        for (int32_t p = xadj[v]; p < xadj[v + 1]; ++p) {
          const int32_t d = map[adj[p]];
          if (d == c) continue;
          if (s.row[d] != c) {
            s.row[d] = c;
            s.slot[d] = static_cast<int32_t>(out.adj.size());
            out.adj.push_back(d);
            if (wgt) out.wgt.push_back(weight(p));
          } else if (wgt) {
            out.wgt[s.slot[d]] += weight(p);
          }
        }
      }
      hx[c + 1] = static_cast<int32_t>(out.adj.size() - row_start);
    }
  };
  if (nb <= 1) {
    if (nb == 1) build(0);
  } else {
    tbb::parallel_for(0, nb, build);
  }
  for (int32_t c = 0; c < nc; ++c) hx[c + 1] += hx[c];
  hadj.resize(static_cast<size_t>(hx[nc]));
  if (wgt) wgt->resize(hadj.size());
  const auto place = [&](int32_t b) {
    const size_t at = static_cast<size_t>(hx[static_cast<size_t>(b) * kContractBlock]);
    std::copy(blocks[b].adj.begin(), blocks[b].adj.end(), hadj.begin() + at);
    if (wgt) std::copy(blocks[b].wgt.begin(), blocks[b].wgt.end(), wgt->begin() + at);
    blocks[b] = Block{};
  };
  if (nb <= 1) {
    if (nb == 1) place(0);
  } else {
    tbb::parallel_for(0, nb, place);
  }
}

// g contracted along map (nc coarse vertices), edge weights summed.
Weighted contract(const Weighted& g, const HostVector<int32_t>& map, int32_t nc) {
  Weighted h;
  contract_rows(g.xadj, g.adj, map, nc, [&w = g.wgt](int32_t p) { return w[p]; }, h.xadj, h.adj, &h.wgt);
  return h;
}

}  // namespace

int32_t coarsening_map(const AdjacencyGraph& g, int levels, HostVector<int32_t>& cmap, ProgressTicker* ticker) {
  // Each step is one pass over the graph (~10-40 ms at 416k): a C host's
  // chance to cancel (its progress callback) comes between them.
  const auto poll = [ticker] {
    if (!ticker) return;
    ticker->tick();
    ticker->context().check_cancel();
  };
  const int32_t n = g.n();
  cmap.resize(static_cast<size_t>(n));
  std::iota(cmap.begin(), cmap.end(), 0);
  Weighted cur;
  cur.xadj.assign(g.xadj.begin(), g.xadj.end());
  cur.adj.assign(g.adj.begin(), g.adj.end());
  cur.wgt.assign(g.adj.size(), 1);
  int32_t nc = n;
  HostVector<int32_t> map;
  for (int level = 0; level < levels && nc > 1; ++level) {
    poll();
    const int32_t next = match(cur, 0x5eed0000ULL + static_cast<uint64_t>(level), map);
    if (next == nc) break;  // nothing matched (no edges)
    for (int32_t& c : cmap) c = map[c];
    poll();
    if (level + 1 < levels) cur = contract(cur, map, next);
    nc = next;
  }
  return nc;
}

AdjacencyGraph contract_graph(const AdjacencyGraph& g, std::span<const int32_t> coarse, int32_t nc,
                              HostVector<int32_t>& vwgt, HostVector<int32_t>* ewgt) {
  vwgt.assign(static_cast<size_t>(nc), 0);
  for (const int32_t c : coarse) ++vwgt[c];
  AdjacencyGraph h;
  contract_rows(g.xadj, g.adj, coarse, nc, [](int32_t) { return 1; }, h.xadj, h.adj, ewgt);
  return h;
}

AdjacencyGraph restrict_contraction(const AdjacencyGraph& h, std::span<const int32_t> keep, int32_t nkept,
                                    std::span<const int32_t> ewgt, HostVector<int32_t>* kept_ewgt) {
  HostVector<int32_t> from(static_cast<size_t>(nkept));  // vertex of h behind each kept one
  for (int32_t c = 0; c < h.n(); ++c)
    if (keep[c] >= 0) from[keep[c]] = c;
  AdjacencyGraph r;
  r.xadj.assign(1, 0);
  r.xadj.reserve(static_cast<size_t>(nkept) + 1);
  if (kept_ewgt) kept_ewgt->clear();
  for (int32_t k = 0; k < nkept; ++k) {
    const int32_t c = from[k];
    for (int32_t p = h.xadj[c]; p < h.xadj[c + 1]; ++p)
      if (const int32_t d = keep[h.adj[p]]; d >= 0) {
        r.adj.push_back(d);
        if (kept_ewgt && !ewgt.empty()) kept_ewgt->push_back(ewgt[p]);
      }
    r.xadj.push_back(static_cast<int32_t>(r.adj.size()));
  }
  return r;
}

}  // namespace locus
