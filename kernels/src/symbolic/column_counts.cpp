// Column counts by row-subtree leaves (kernels/include/locus/kernels/symbolic/column_counts.hpp).
//
// For each row i, the leaves of its row subtree are the columns j < i with
// A_ij != 0 whose subtree does not contain an earlier such column (tested with
// first-descendant indices in postorder). Each leaf adds one to its column;
// the least common ancestor of consecutive leaves subtracts one (found with a
// disjoint-set forest over processed nodes). Each non-root node subtracts one
// from its parent, and summing over subtrees gives the counts.
//
// Over subtrees (column_counts_postordered): every contribution is a +1 or
// -1 at a node, so the sweep can be cut anywhere the contributions can be
// attributed. A piece's own rows are complete inside it; for a row above, the
// -1 linking the leaf before the piece to its first leaf in it lands on a
// top node and is found in the top pass from the last leaf handed over.
#include "locus/kernels/symbolic/column_counts.hpp"
#include "locus/core/host_allocator.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <tuple>
#include <vector>

namespace locus {

HostVector<int32_t> column_counts(int32_t n, std::span<const int64_t> ptr, std::span<const int32_t> idx,
                                   std::span<const int32_t> parent, std::span<const int32_t> post) {
  HostVector<int32_t> delta(n, 0), first(n, -1), maxfirst(n, -1), prevleaf(n, -1), ancestor(n);
  for (int32_t k = 0; k < n; ++k) {
    int32_t j = post[k];
    delta[j] = (first[j] == -1) ? 1 : 0;  // etree leaves start with their diagonal
    for (; j != -1 && first[j] == -1; j = parent[j]) first[j] = k;
  }
  for (int32_t i = 0; i < n; ++i) ancestor[i] = i;
  for (int32_t k = 0; k < n; ++k) {
    cancel_point(k);
    const int32_t j = post[k];
    if (parent[j] != -1) --delta[parent[j]];
    for (int64_t p = ptr[j]; p < ptr[j + 1]; ++p) {
      const int32_t i = idx[p];
      if (i <= j || first[j] <= maxfirst[i]) continue;  // j is not a leaf of T_r(i)
      maxfirst[i] = first[j];
      const int32_t jprev = prevleaf[i];
      prevleaf[i] = j;
      ++delta[j];
      if (jprev != -1) {
        // q = root of jprev's set = least common ancestor of jprev and j.
        int32_t q = jprev;
        while (q != ancestor[q]) q = ancestor[q];
        for (int32_t s = jprev; s != q;) {  // path compression
          const int32_t next = ancestor[s];
          ancestor[s] = q;
          s = next;
        }
        --delta[q];
      }
    }
    if (parent[j] != -1) ancestor[j] = parent[j];
  }
  for (int32_t j = 0; j < n; ++j)  // parent[j] > j: ascending order sums children first
    if (parent[j] != -1) delta[parent[j]] += delta[j];
  return delta;
}

namespace {

// State of one column_counts_postordered call. Row i's state (the first
// descendant of its last leaf, and that leaf) lives in maxfirst/prevleaf when
// i is in the piece being swept or a top node swept by the top pass; pieces
// keep the state of rows above them in thread-local arrays (Outside).
struct CountSweep {
  std::span<const int64_t> ptr;
  std::span<const int32_t> idx, parent;
  HostVector<int32_t> delta, first, maxfirst, prevleaf, ancestor;

  // Root of a's set = the least common ancestor sought (path compression;
  // only nodes of the caller's piece, or top nodes in the top pass, move).
  int32_t find(int32_t a) {
    int32_t q = a;
    while (q != ancestor[q]) q = ancestor[q];
    for (int32_t s = a; s != q;) {
      const int32_t next = ancestor[s];
      ancestor[s] = q;
      s = next;
    }
    return q;
  }
  // Column j's rows: leaves of row subtrees. state(i) returns row i's
  // (maxfirst, prevleaf) references; lca(q) takes the -1 of a least common ancestor.
  template <class State, class Lca>
  void sweep(int32_t j, State&& state, Lca&& lca) {
    for (int64_t p = ptr[j]; p < ptr[j + 1]; ++p) {
      const int32_t i = idx[p];
      if (i <= j) continue;
      auto [mf, pl] = state(i);
      if (first[j] <= mf) continue;  // j is not a leaf of T_r(i)
      mf = first[j];
      const int32_t jprev = pl;
      pl = j;
      ++delta[j];
      if (jprev != -1) lca(find(jprev));
    }
  }
};

// A piece's hand-over to the top pass.
struct PieceResult {
  HostVector<int32_t> rows, last_leaf;  // rows above the piece with leaves in it, and their last leaf
  HostVector<int32_t> top_minus;                   // -1s that fall on top nodes
  HostVector<int32_t> roots;                       // nodes whose parent is a top node
};

// Thread-local state of the rows above the piece being swept: they are top
// nodes (ancestors of the piece's roots), indexed by their rank among them.
struct Outside {
  HostVector<int32_t> maxfirst, prevleaf;
};

void sweep_piece(CountSweep& c, int32_t b, int32_t e, std::span<const int32_t> top_rank, Outside& out,
                 PieceResult& r) {
  for (int32_t j = b; j < e; ++j) {
    cancel_point(j);
    const int32_t pj = c.parent[j];
    if (pj >= e) r.top_minus.push_back(pj);
    else if (pj != -1) --c.delta[pj];
    const auto state = [&](int32_t i) {
      if (i < e) return std::tie(c.maxfirst[i], c.prevleaf[i]);
      const int32_t t = top_rank[i];
      if (out.prevleaf[t] == -1) r.rows.push_back(i);  // i's first leaf in this piece (always a leaf)
      return std::tie(out.maxfirst[t], out.prevleaf[t]);
    };
    const auto lca = [&](int32_t q) {
      if (q < e) --c.delta[q];
      else r.top_minus.push_back(q);  // leaves in two subtrees of a joined piece
    };
    c.sweep(j, state, lca);
    if (pj != -1) c.ancestor[j] = pj;
  }
  r.last_leaf.resize(r.rows.size());
  for (size_t t = 0; t < r.rows.size(); ++t) {
    const int32_t i = top_rank[r.rows[t]];
    r.last_leaf[t] = out.prevleaf[i];
    out.prevleaf[i] = out.maxfirst[i] = -1;
  }
  for (int32_t j = b; j < e; ++j) {  // subtree sums inside the piece
    const int32_t pj = c.parent[j];
    if (pj >= e) r.roots.push_back(j);
    else if (pj != -1) c.delta[pj] += c.delta[j];
  }
}

}  // namespace

HostVector<int32_t> column_counts_postordered(int32_t n, std::span<const int64_t> ptr, std::span<const int32_t> idx,
                                              std::span<const int32_t> parent, const SubtreePartition& part) {
  CountSweep c{ptr, idx, parent, HostVector<int32_t>(n, 0), HostVector<int32_t>(n), HostVector<int32_t>(n, -1),
               HostVector<int32_t>(n, -1), HostVector<int32_t>(n)};
  for (int32_t j = 0; j < n; ++j) c.first[j] = c.ancestor[j] = j;
  for (int32_t j = 0; j < n; ++j)
    if (parent[j] != -1) c.first[parent[j]] = std::min(c.first[parent[j]], c.first[j]);
  for (int32_t j = 0; j < n; ++j) c.delta[j] = c.first[j] == j ? 1 : 0;  // etree leaves start with their diagonal

  const int32_t np = part.num_pieces();
  std::vector<PieceResult> res(static_cast<size_t>(np));
  const size_t ntop = part.top.size();
  HostVector<int32_t> top_rank(ntop > 0 ? n : 0, -1);
  for (size_t t = 0; t < ntop; ++t) top_rank[part.top[t]] = static_cast<int32_t>(t);
  tbb::enumerable_thread_specific<Outside> outside([ntop] {
    return Outside{HostVector<int32_t>(ntop, -1), HostVector<int32_t>(ntop, -1)};
  });
  const auto piece = [&](int32_t q) {
    sweep_piece(c, part.piece_begin[q], part.piece_end[q], top_rank, outside.local(), res[q]);
  };
  if (np == 1) piece(0);
  else tbb::parallel_for(0, np, piece);

  // The top pass in postorder: pieces (their hand-over) and top nodes interleaved.
  const auto top_lca = [&](int32_t q) { --c.delta[q]; };
  const auto top_state = [&](int32_t i) { return std::tie(c.maxfirst[i], c.prevleaf[i]); };
  int32_t q = 0;
  for (size_t t = 0; t <= part.top.size(); ++t) {
    const int32_t j = t < part.top.size() ? part.top[t] : n;
    for (; q < np && part.piece_begin[q] < j; ++q) {
      const PieceResult& r = res[q];
      for (int32_t m : r.top_minus) --c.delta[m];
      for (size_t u = 0; u < r.rows.size(); ++u) {
        const int32_t i = r.rows[u];
        if (c.prevleaf[i] != -1) --c.delta[c.find(c.prevleaf[i])];
        c.prevleaf[i] = r.last_leaf[u];
        c.maxfirst[i] = c.first[r.last_leaf[u]];
      }
    }
    if (j == n) break;
    cancel_point(static_cast<int64_t>(t));
    if (parent[j] != -1) --c.delta[parent[j]];
    c.sweep(j, top_state, top_lca);
    if (parent[j] != -1) c.ancestor[j] = parent[j];
  }
  // Subtree sums above the pieces, children before parents.
  q = 0;
  for (size_t t = 0; t < part.top.size(); ++t) {
    const int32_t j = part.top[t];
    for (; q < np && part.piece_begin[q] < j; ++q)
      for (int32_t r : res[q].roots) c.delta[parent[r]] += c.delta[r];
    if (parent[j] != -1) c.delta[parent[j]] += c.delta[j];
  }
  return std::move(c.delta);
}

}  // namespace locus
