// Shared coarsening (kernels/include/locus/kernels/order/graph_coarsening.hpp).
#include "locus/kernels/order/graph_coarsening.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <numeric>
#include <tuple>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "locus/core/default_init_allocator.hpp"
#include "locus/core/host_allocator.hpp"

namespace locus {

namespace {

// Scratch arrays are not zeroed on allocation: fresh memory costs a page
// fault per 4 KiB on first touch (~6 ms per 16 MB here, a quarter of the
// coarsening at 416k), and zeroing would take them all on one thread up
// front. Each array's first writes are the parallel passes that fill it.
template <class T>
using Scratch = std::vector<T, DefaultInitAllocator<T>>;

// A graph with edge multiplicities whose rows may have gaps between them:
// row v is adj[beg[v]] .. adj[end[v] - 1] (a contraction writes each row
// within room for its fine rows and leaves it there: no second copy).
struct Weighted {
  Scratch<int32_t> beg, end, adj, wgt;
};
// The graph one matching round works on; wgt empty: every edge counts 1
// (the input graph, with end = xadj + 1, matched without copying it).
struct GraphView {
  const int32_t* beg;
  const int32_t* end;
  int32_t nv;
  std::span<const int32_t> adj, wgt;
  int32_t n() const { return nv; }
  int32_t degree(int32_t v) const { return end[v] - beg[v]; }
  int32_t weight(int32_t p) const { return wgt.empty() ? 1 : wgt[p]; }
};

// The last tie-break of an edge {a, b}: a mix of the pair (symmetric: of
// a + b and a ^ b) and the round's seed, so that a vertex's preference among
// equal neighbors is pseudo-random, not by index. 32 bits: two edges of one
// vertex tie ~1 in 4 billion times (see handshake_matching).
uint32_t edge_hash(int32_t a, int32_t b, uint64_t seed) {
  const uint64_t sum = static_cast<uint32_t>(static_cast<uint32_t>(a) + static_cast<uint32_t>(b));
  const uint64_t diff = static_cast<uint32_t>(a ^ b);
  const uint64_t x = (((sum << 32) | diff) ^ seed) * 0x9e3779b97f4a7c15ULL;
  return static_cast<uint32_t>(x >> 32);
}

// The rank of edge {v, w} from v's side: a heavier edge first, then a
// neighbor with fewer neighbors, then a higher edge_hash. v's own degree
// being fixed, that is the order of the symmetric key (weight, -(deg v +
// deg w), hash): the same order from both ends. One integer (weights and
// degrees above 65535 count as 65535), so that picking the best takes no
// unpredictable branch: the branches on the ranks, not the random reads,
// were the matching's cost.
uint64_t rank_of(int32_t weight, int32_t degree, uint32_t hash) {
  const uint64_t w = static_cast<uint64_t>(std::min(weight, 0xffff));
  const uint64_t d = static_cast<uint64_t>(0xffff - std::min(degree, 0xffff));
  return (w << 48) | (d << 32) | hash;
}

// v's two favourite unmatched neighbors (-1: none). free_deg[w] = degree of
// w while w is unmatched, -1 once matched.
std::pair<int32_t, int32_t> favourites(const GraphView& g, int32_t v, const int32_t* free_deg, uint64_t seed) {
  int32_t first = -1, second = -1;
  uint64_t r1 = 0, r2 = 0;  // 0: none (every edge ranks above: weight >= 1)
  // Selections by masks: compilers turn conditional moves of this loop into
  // branches, which the random ranks mispredict half of the time.
  const auto pick = [](uint64_t mask, auto yes, auto no) {
    using T = decltype(yes);
    return static_cast<T>((static_cast<uint64_t>(yes) & mask) | (static_cast<uint64_t>(no) & ~mask));
  };
  for (int32_t p = g.beg[v]; p < g.end[v]; ++p) {
    const int32_t w = g.adj[p];
    const int32_t dw = free_deg[w];
    const uint64_t valid = 0 - static_cast<uint64_t>((dw >= 0) & (w != v));
    const uint64_t r = rank_of(g.weight(p), dw, edge_hash(v, w, seed)) & valid;
    const uint64_t above1 = 0 - static_cast<uint64_t>(r > r1), above2 = 0 - static_cast<uint64_t>(r > r2);
    r2 = pick(above1, r1, pick(above2, r, r2));
    second = pick(above1, first, pick(above2, w, second));
    r1 = pick(above1, r, r1);
    first = pick(above1, w, first);
  }
  return {first, second};
}

// The matching's arrays, kept from one level to the next.
struct MatchSpace {
  Scratch<int32_t> mate, free_deg, fav, next, active, spare;  // active, spare: lists
};

// Heavy-edge matching by handshakes: every unmatched vertex points at its
// favourite unmatched neighbor, mutual pointers match, repeat. The edge of
// the highest rank among the unmatched is mutual, so every round matches
// some (at 416k, 7 rounds leave a few dozen vertices to check), and the
// result is the greedy matching in decreasing rank order (up to the rare
// equal ranks) whatever the thread count: rounds are synchronous, a round
// reading only the previous rounds' matches. After kMaxRounds (never
// reached on the meshes) the rest are matched in index order, one thread.
// Leaves ms.mate[v] (v itself: left single).

void handshake_matching(const GraphView& g, uint64_t seed, MatchSpace& ms) {
  const int32_t n = g.n();
  for (Scratch<int32_t>* a : {&ms.mate, &ms.free_deg, &ms.fav, &ms.next, &ms.active, &ms.spare})
    a->resize(static_cast<size_t>(n));
  int32_t* const mate = ms.mate.data();
  int32_t* const free_deg = ms.free_deg.data();
  int32_t* const fav = ms.fav.data();
  int32_t* const next = ms.next.data();
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, n, 4096), [&](const tbb::blocked_range<int32_t>& r) {
    for (int32_t v = r.begin(); v < r.end(); ++v) {
      mate[v] = v;
      free_deg[v] = g.degree(v);
      ms.active[v] = v;
    }
  });
  // A favourite changes only when it is matched (the unmatched only shrink);
  // then the runner-up of the last scan, if still unmatched, is the new
  // favourite (next[v] == -2: unknown, scan again).
  const auto update = [&](int32_t v, bool first) {
    if (!first && free_deg[fav[v]] >= 0) return;
    if (!first && next[v] != -2 && (next[v] < 0 || free_deg[next[v]] >= 0)) {
      fav[v] = next[v];
      next[v] = -2;
    } else {
      std::tie(fav[v], next[v]) = favourites(g, v, free_deg, seed);
    }
  };
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, n, 2048), [&](const tbb::blocked_range<int32_t>& r) {
    for (int32_t v = r.begin(); v < r.end(); ++v) update(v, true);
  });
  // Each round: the handshakes and the count of the still unmatched vertices
  // with a favourite per fixed block of the list (one pass), then their
  // list packed block by block with their favourites updated (another).
  constexpr int kMaxRounds = 32;
  constexpr size_t kBlock = 4096;
  size_t count = static_cast<size_t>(n);
  std::vector<size_t> first;
  const auto keep = [&](int32_t v) { return free_deg[v] >= 0 && fav[v] >= 0; };
  for (int round = 0; count > 0; ++round) {
    const int32_t* const list = ms.active.data();
    const size_t nb = (count + kBlock - 1) / kBlock;
    first.assign(nb + 1, 0);
    tbb::parallel_for(size_t{0}, nb, [&](size_t b) {
      size_t k = 0;
      for (size_t i = b * kBlock; i < std::min(count, (b + 1) * kBlock); ++i) {
        const int32_t v = list[i];
        if (fav[v] >= 0 && fav[fav[v]] == v) {
          mate[v] = fav[v];
          free_deg[v] = -1;
        }
        k += keep(v);
      }
      first[b + 1] = k;
    });
    for (size_t b = 0; b < nb; ++b) first[b + 1] += first[b];
    const bool last = round + 1 == kMaxRounds;
    int32_t* const out = ms.spare.data();
    tbb::parallel_for(size_t{0}, nb, [&](size_t b) {
      size_t at = first[b];
      for (size_t i = b * kBlock; i < std::min(count, (b + 1) * kBlock); ++i)
        if (const int32_t v = list[i]; keep(v)) {
          out[at++] = v;
          if (!last) update(v, false);
        }
    });
    std::swap(ms.active, ms.spare);
    count = first[nb];
    if (last) break;
  }
  for (size_t i = 0; i < count; ++i)
    if (const int32_t v = ms.active[i]; free_deg[v] >= 0)
      if (const int32_t w = favourites(g, v, free_deg, seed).first; w >= 0) {
        mate[v] = w;
        mate[w] = v;
        free_deg[v] = free_deg[w] = -1;
      }
}

// Vertices per block of the numbering below (fixed: the same numbers for
// any thread count).
constexpr int32_t kNumberBlock = 16384;

// Coarse numbers of a matching: pairs and singles numbered in ascending order
// of their lower vertex (lead[c]); map[v] in [0, returned count).
int32_t number_pairs(const Scratch<int32_t>& mate, Scratch<int32_t>& map, Scratch<int32_t>& lead) {
  const int32_t n = static_cast<int32_t>(mate.size());
  const int32_t nb = (n + kNumberBlock - 1) / kNumberBlock;
  Scratch<int32_t> first(static_cast<size_t>(nb) + 1, 0);
  tbb::parallel_for(0, nb, [&](int32_t b) {
    int32_t k = 0;
    for (int32_t v = b * kNumberBlock; v < std::min(n, (b + 1) * kNumberBlock); ++v) k += mate[v] >= v;
    first[b + 1] = k;
  });
  for (int32_t b = 0; b < nb; ++b) first[b + 1] += first[b];
  const int32_t nc = first[nb];
  map.resize(static_cast<size_t>(n));
  lead.resize(static_cast<size_t>(nc));
  tbb::parallel_for(0, nb, [&](int32_t b) {
    int32_t c = first[b];
    for (int32_t v = b * kNumberBlock; v < std::min(n, (b + 1) * kNumberBlock); ++v)
      if (mate[v] >= v) {
        map[v] = c;
        lead[c++] = v;
      }
  });
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, n, 4096), [&](const tbb::blocked_range<int32_t>& r) {
    for (int32_t v = r.begin(); v < r.end(); ++v)
      if (mate[v] < v) map[v] = map[mate[v]];
  });
  return nc;
}

// Coarse rows per block of the contraction below: blocks are built in
// parallel, each row depending on its coarse vertex only, so the result is
// the same for any thread count (and equal to one sequential pass).
constexpr int32_t kContractBlock = 4096;

// Scratch of the contraction, kept from one level to the next: fresh memory
// costs a page fault per 4 KiB on first touch, ~6 ms per 16 MB here, as much
// as the contraction's own work at 416k.
struct ContractSpace {
  HostVector<size_t> base;
  tbb::enumerable_thread_specific<Scratch<int32_t>> row, slot;  // see contract_rows
};

// The rows of g contracted along map[v] in [0, nc), written into (adj, wgt)
// with gaps: row c is adj[beg[c]] .. adj[end[c] - 1], coarse neighbors in
// order of first appearance (members ascending, each one's list in order),
// self loops dropped; with wgt, wgt[q] = the sum of g.weight(p) over the
// fine edges p behind coarse edge q. members(c, f) calls f(v) for the
// vertices v of c, ascending. Coarse rows in fixed blocks, in parallel
// (the caller's arena): the same rows for any thread count.
template <class Members>
void contract_rows(const GraphView& g, std::span<const int32_t> map, int32_t nc, Members members,
                   Scratch<int32_t>& beg, Scratch<int32_t>& end, Scratch<int32_t>& adj, Scratch<int32_t>* wgt,
                   ContractSpace& ws) {
  constexpr int32_t kShortRow = 48;  // fine entries of a row deduplicated locally
  const int32_t nb = (nc + kContractBlock - 1) / kContractBlock;
  const auto for_blocks = [nb](auto&& f) {
    if (nb == 1) f(0);
    else if (nb > 1) tbb::parallel_for(0, nb, f);
  };
  // Room for each block: its members' degrees, and a spare entry per row.
  ws.base.assign(static_cast<size_t>(nb) + 1, 0);
  for_blocks([&](int32_t b) {
    size_t room = 0;
    for (int32_t c = b * kContractBlock; c < std::min(nc, (b + 1) * kContractBlock); ++c) {
      room += 1;
      members(c, [&](int32_t v) { room += static_cast<size_t>(g.degree(v)); });
    }
    ws.base[b + 1] = room;
  });
  for (int32_t b = 0; b < nb; ++b) ws.base[b + 1] += ws.base[b];
  if (ws.base[nb] > static_cast<size_t>(INT32_MAX))
    throw std::length_error("graph coarsening: more than 2^31 entries");  // fewer than g's own
  adj.resize(ws.base[nb]);
  if (wgt) wgt->resize(ws.base[nb]);
  beg.resize(static_cast<size_t>(nc));
  end.resize(static_cast<size_t>(nc));
  // row[d] == c: d is in row c already, at slot[d]. A row is built without
  // a branch on that test (a random one, mispredicted in a third of the
  // edges): a repeated neighbor is written again over itself, a self loop
  // into the row's spare entry past its end.
  for_blocks([&](int32_t b) {
    Scratch<int32_t>& row_v = ws.row.local();
    Scratch<int32_t>& slot_v = ws.slot.local();
    if (row_v.size() < static_cast<size_t>(nc)) {
      row_v.assign(static_cast<size_t>(nc), -1);
      slot_v.assign(static_cast<size_t>(nc), 0);
    }
    int32_t* const row = row_v.data();
    int32_t* const slot = slot_v.data();
    int32_t* const a = adj.data();
    int32_t* const wt = wgt ? wgt->data() : nullptr;
    auto len = static_cast<int32_t>(ws.base[b]);
    for (int32_t c = b * kContractBlock; c < std::min(nc, (b + 1) * kContractBlock); ++c) {
      beg[c] = len;
      int32_t spare = len;
      members(c, [&](int32_t v) { spare += g.degree(v); });
      if (spare - len <= kShortRow) {
        // Short row: the coarse neighbors gathered first (independent
        // random reads that overlap), then deduplicated among themselves.
        int32_t d[kShortRow], w[kShortRow];
        int32_t k = 0;
        members(c, [&](int32_t v) {
          for (int32_t p = g.beg[v]; p < g.end[v]; ++p, ++k) {
            d[k] = map[g.adj[p]];
            w[k] = g.weight(p);
          }
        });
        const int32_t start = len;
        for (int32_t i = 0; i < k; ++i) {
          if (d[i] == c) continue;
          int32_t at = start;
          while (at < len && a[at] != d[i]) ++at;
          if (at == len) {
            a[len++] = d[i];
            if (wt) wt[at] = 0;
          }
          if (wt) wt[at] += w[i];
        }
        end[c] = len;
        continue;
      }
      row[c] = c;
      slot[c] = spare;
      members(c, [&](int32_t v) {
        for (int32_t p = g.beg[v]; p < g.end[v]; ++p) {
          const int32_t d = map[g.adj[p]];
          const bool seen = row[d] == c;
          const int32_t mask = -static_cast<int32_t>(seen);
          const int32_t at = (slot[d] & mask) | (len & ~mask);
          a[at] = d;
          if (wt) {
            wt[len] = 0;
            wt[at] += g.weight(p);
          }
          row[d] = c;
          slot[d] = at;
          len += !seen;
        }
      });
      end[c] = len;
    }
  });
  // Marks of this call must not meet the next call's coarse numbers.
  for (auto& r : ws.row) std::fill(r.begin(), r.end(), -1);
}

// g contracted along a matching (number_pairs: lead, map; mate), edge
// weights summed, into h: coarse vertex c is lead[c] and its mate.
void contract_pairs(const GraphView& g, const Scratch<int32_t>& map, const Scratch<int32_t>& lead,
                    const Scratch<int32_t>& mate, Weighted& h, ContractSpace& ws) {
  const auto members = [&](int32_t c, auto&& f) {
    const int32_t v = lead[c];
    f(v);
    if (mate[v] != v) f(mate[v]);
  };
  contract_rows(g, map, static_cast<int32_t>(lead.size()), members, h.beg, h.end, h.adj, &h.wgt, ws);
}

// The graph of `view` without gaps between its rows; with ewgt, its edge
// weights too (1 for an unweighted view). Rows in parallel blocks.
AdjacencyGraph compact_rows(const GraphView& view, HostVector<int32_t>* ewgt) {
  const int32_t nv = view.n();
  AdjacencyGraph h;
  h.xadj.resize(static_cast<size_t>(nv) + 1);
  h.xadj[0] = 0;
  for (int32_t c = 0; c < nv; ++c) h.xadj[c + 1] = h.xadj[c] + view.degree(c);
  h.adj.resize(static_cast<size_t>(h.xadj[nv]));
  if (ewgt) ewgt->resize(h.adj.size());
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, nv, kContractBlock), [&](const tbb::blocked_range<int32_t>& r) {
    for (int32_t c = r.begin(); c < r.end(); ++c)
      for (int32_t p = view.beg[c], q = h.xadj[c]; p < view.end[c]; ++p, ++q) {
        h.adj[q] = view.adj[p];
        if (ewgt) (*ewgt)[q] = view.weight(p);
      }
  });
  return h;
}

}  // namespace

int32_t coarsening_map(const AdjacencyGraph& g, int levels, HostVector<int32_t>& cmap, ProgressTicker* ticker,
                       Contraction* coarsest) {
  // Each step is one pass over the graph (~10-40 ms at 416k): a C host's
  // chance to cancel (its progress callback) comes between them.
  const auto poll = [ticker] {
    if (!ticker) return;
    ticker->tick();
    ticker->context().check_cancel();
  };
  const int32_t n = g.n();
  Weighted levels_g[2];  // the graphs of the levels after the first, alternating
  GraphView view{g.xadj.data(), g.xadj.data() + 1, n, g.adj, {}};  // the current level's graph: g itself first
  std::vector<Scratch<int32_t>> maps;  // maps[k][v]: v's vertex at level k + 1
  MatchSpace ms;
  ContractSpace cs;
  int32_t nc = n;
  Scratch<int32_t> lead;
  for (int level = 0; level < levels && nc > 1; ++level) {
    poll();
    handshake_matching(view, 0x5eed0000ULL + static_cast<uint64_t>(level), ms);
    Scratch<int32_t> map;
    const int32_t next = number_pairs(ms.mate, map, lead);
    if (next == nc) break;  // nothing matched (no edges)
    poll();
    // The last level's graph only when the caller wants it: from the level
    // above, a pass over ~2^(levels-1) times fewer rows than contract_graph's.
    if (level + 1 < levels || coarsest) {
      Weighted& h = levels_g[level % 2];
      contract_pairs(view, map, lead, ms.mate, h, cs);
      view = GraphView{h.beg.data(), h.end.data(), next, h.adj, h.wgt};
    }
    maps.push_back(std::move(map));
    nc = next;
  }
  if (coarsest) coarsest->graph = compact_rows(view, &coarsest->ewgt);
  // Composed from the coarsest level down: each pass is over one level's
  // vertices (n + n/2 + ... instead of levels x n random reads).
  for (size_t k = maps.size(); k-- > 1;) {
    Scratch<int32_t>& fine = maps[k - 1];
    const Scratch<int32_t>& coarse = maps[k];
    tbb::parallel_for(tbb::blocked_range<size_t>(0, fine.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t v = r.begin(); v < r.end(); ++v) fine[v] = coarse[fine[v]];
    });
  }
  cmap.resize(static_cast<size_t>(n));
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, n, 4096), [&](const tbb::blocked_range<int32_t>& r) {
    for (int32_t v = r.begin(); v < r.end(); ++v) cmap[v] = maps.empty() ? v : maps[0][v];
  });
  return nc;
}

AdjacencyGraph contract_graph(const AdjacencyGraph& g, std::span<const int32_t> coarse, int32_t nc,
                              HostVector<int32_t>& vwgt, HostVector<int32_t>* ewgt) {
  const int32_t n = g.n();
  HostVector<int32_t> start(static_cast<size_t>(nc) + 1, 0), members(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) ++start[coarse[v] + 1];
  vwgt.assign(start.begin() + 1, start.end());  // members per coarse vertex
  for (int32_t c = 0; c < nc; ++c) start[c + 1] += start[c];
  {
    HostVector<int32_t> pos(start.begin(), start.end() - 1);
    for (int32_t v = 0; v < n; ++v) members[pos[coarse[v]]++] = v;
  }
  const auto each = [&](int32_t c, auto&& f) {
    for (int32_t q = start[c]; q < start[c + 1]; ++q) f(members[q]);
  };
  ContractSpace ws;
  Weighted rows;
  const GraphView view{g.xadj.data(), g.xadj.data() + 1, n, g.adj, {}};
  contract_rows(view, coarse, nc, each, rows.beg, rows.end, rows.adj, ewgt ? &rows.wgt : nullptr, ws);
  return compact_rows(GraphView{rows.beg.data(), rows.end.data(), nc, rows.adj, rows.wgt}, ewgt);
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
