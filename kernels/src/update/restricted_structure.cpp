// The restricted supernodal structure of the factor-once update (thesis §5.5;
// declared in restricted_structure.hpp): restriction of every global supernode
// to I, its postorder when I splits a subtree, and the parts of the symbolic
// factor that do not involve A. Closure of the restricted structure: see the
// essay atop factor_update.cpp.
#include "restricted_structure.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <utility>

#include "locus/kernels/symbolic/etree.hpp"

namespace locus::update_detail {

namespace {

// Rows of the global supernodes holding gcol[c0, c1): a bound of their restricted rows.
int64_t rows_bound(const SymbolicFactor& S, const std::vector<int32_t>& gcol, int32_t c0, int32_t c1) {
  int64_t bound = 0;
  for (int32_t c = c0, prev = -1; c < c1; ++c) {
    const int32_t s = S.col_to_super[gcol[c]];
    if (s != prev) bound += S.nrows(s);
    prev = s;
  }
  return bound;
}

// The restricted supernodes of the global supernodes that hold columns
// gcol[c0, c1) (c0 and c1 at supernode boundaries), in lists of their own
// (gsuper, first_col and row_ptr without the leading entries, rows, rowpos;
// rows reserved for `reserve` entries); colpos is written at [c0, c1). The
// lists live in this call's frame, not beside the other half's: vectors side
// by side share the cache lines of their end pointers (false sharing, see
// docs/factor_update.md).
Restricted restrict_range(const SymbolicFactor& S, const std::vector<int32_t>& col_new, const std::vector<int32_t>& gcol,
                          int32_t* colpos, int32_t c0, int32_t c1, int64_t reserve) {
  Restricted H;
  H.rows.reserve(static_cast<size_t>(reserve));
  H.rowpos.reserve(static_cast<size_t>(reserve));
  for (int32_t c = c0; c < c1;) {
    const int32_t s = S.col_to_super[gcol[c]];
    const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
    int32_t c2 = c;
    while (c2 < c1 && gcol[c2] < l) {
      colpos[c2] = gcol[c2] - f;
      ++c2;
    }
    H.gsuper.push_back(s);
    H.first_col.push_back(c2);
    const int64_t r0 = S.super_row_ptr[s], nr = S.nrows(s);
    for (int64_t t = 0; t < nr; ++t) {
      const int32_t r = col_new[S.super_rows[r0 + t]];
      if (r >= 0) {
        H.rows.push_back(r);
        H.rowpos.push_back(static_cast<int32_t>(t));
      }
    }
    H.row_ptr.push_back(static_cast<int64_t>(H.rows.size()));
    c = c2;
  }
  return H;
}

// True when every subtree of the topologically ordered tree (parent > child)
// is the contiguous range ending at its root, i.e. the order is a postorder.
bool is_postorder(const std::vector<int32_t>& parent) {
  const int32_t ns = static_cast<int32_t>(parent.size());
  std::vector<int32_t> size(ns, 1), first(ns);
  for (int32_t s = 0; s < ns; ++s) first[s] = s;
  for (int32_t s = 0; s < ns; ++s) {
    if (s - first[s] + 1 != size[s]) return false;
    const int32_t p = parent[s];
    if (p >= 0) {
      size[p] += size[s];
      first[p] = std::min(first[p], first[s]);
    }
  }
  return true;
}

}  // namespace

// With two threads the touched supernodes are split at a supernode boundary
// near the middle column and restricted side by side; the second half is
// appended to the first, so the result is the same as one pass.
Restricted restrict_structure(const SymbolicFactor& S, const std::vector<int32_t>& col_new, std::vector<int32_t> gcol,
                              bool two_threads) {
  const int32_t m = static_cast<int32_t>(gcol.size());
  std::vector<int32_t> colpos(m);
  // Room for every row at once: appending the second half copies nothing else.
  const int64_t bound = rows_bound(S, gcol, 0, m);
  int32_t mid = m / 2;
  while (mid > 0 && mid < m && S.col_to_super[gcol[mid]] == S.col_to_super[gcol[mid - 1]]) ++mid;
  Restricted R;
  if (!two_threads || bound < kSplitRows || mid <= 0 || mid >= m) {
    R = restrict_range(S, col_new, gcol, colpos.data(), 0, m, bound);
  } else {
    Restricted H;  // the second half (colpos is shared: disjoint ranges)
    tbb::parallel_invoke([&] { R = restrict_range(S, col_new, gcol, colpos.data(), 0, mid, bound); },
                         [&] { H = restrict_range(S, col_new, gcol, colpos.data(), mid, m, rows_bound(S, gcol, mid, m)); });
    const int64_t off = static_cast<int64_t>(R.rows.size());
    R.gsuper.insert(R.gsuper.end(), H.gsuper.begin(), H.gsuper.end());
    R.first_col.insert(R.first_col.end(), H.first_col.begin(), H.first_col.end());
    for (const int64_t q : H.row_ptr) R.row_ptr.push_back(off + q);
    R.rows.insert(R.rows.end(), H.rows.begin(), H.rows.end());
    R.rowpos.insert(R.rowpos.end(), H.rowpos.begin(), H.rowpos.end());
  }
  R.first_col.insert(R.first_col.begin(), 0);
  R.row_ptr.insert(R.row_ptr.begin(), 0);
  R.gcol = std::move(gcol);
  R.colpos = std::move(colpos);
  R.ns = static_cast<int32_t>(R.gsuper.size());
  std::vector<int32_t> col_to_super(m);
  for (int32_t s = 0; s < R.ns; ++s)
    for (int32_t c = R.first_col[s]; c < R.first_col[s + 1]; ++c) col_to_super[c] = s;
  R.parent.assign(R.ns, -1);
  for (int32_t s = 0; s < R.ns; ++s) {
    const int64_t below = R.row_ptr[s] + (R.first_col[s + 1] - R.first_col[s]);
    if (below < R.row_ptr[s + 1]) R.parent[s] = col_to_super[R.rows[below]];
  }
  return R;
}

bool postorder_in_place(Restricted& R, bool two_threads) {
  if (is_postorder(R.parent)) return false;
  const HostVector<int32_t> post = tree_postorder(R.parent);
  const int32_t m = static_cast<int32_t>(R.gcol.size());
  std::vector<int32_t> new_of_old(R.ns);
  for (int32_t k = 0; k < R.ns; ++k) new_of_old[post[k]] = k;
  Restricted Q;
  Q.ns = R.ns;
  Q.gsuper.resize(R.ns);
  Q.parent.resize(R.ns);
  Q.first_col.assign(static_cast<size_t>(R.ns) + 1, 0);
  for (int32_t k = 0; k < R.ns; ++k) {
    const int32_t s = post[k];
    Q.gsuper[k] = R.gsuper[s];
    Q.parent[k] = R.parent[s] < 0 ? -1 : new_of_old[R.parent[s]];
    Q.first_col[k + 1] = Q.first_col[k] + (R.first_col[s + 1] - R.first_col[s]);
  }
  std::vector<int32_t> colmap(m);
  Q.gcol.resize(m);
  Q.colpos.resize(m);
  for (int32_t s = 0; s < R.ns; ++s) {
    const int32_t k = new_of_old[s];
    for (int32_t c = R.first_col[s]; c < R.first_col[s + 1]; ++c) {
      const int32_t nc = Q.first_col[k] + (c - R.first_col[s]);
      colmap[c] = nc;
      Q.gcol[nc] = R.gcol[c];
      Q.colpos[nc] = R.colpos[c];
    }
  }
  Q.row_ptr.assign(static_cast<size_t>(R.ns) + 1, 0);
  for (int32_t k = 0; k < R.ns; ++k) Q.row_ptr[k + 1] = Q.row_ptr[k] + (R.row_ptr[post[k] + 1] - R.row_ptr[post[k]]);
  Q.rows.resize(R.rows.size());
  Q.rowpos.resize(R.rowpos.size());
  auto map_rows = [&](int32_t k0, int32_t k1) {
    std::vector<std::pair<int32_t, int32_t>> tmp;
    for (int32_t k = k0; k < k1; ++k) {
      const int32_t s = post[k];
      const int64_t q0 = Q.row_ptr[k], len = Q.row_ptr[k + 1] - q0;
      // The rows of a closed structure lie on the supernode's path to the root,
      // and both orders number a path increasingly: mapping keeps them sorted.
      bool sorted = true;
      for (int64_t t = 0; t < len; ++t) {
        Q.rows[q0 + t] = colmap[R.rows[R.row_ptr[s] + t]];
        Q.rowpos[q0 + t] = R.rowpos[R.row_ptr[s] + t];
        sorted = sorted && (t == 0 || Q.rows[q0 + t] > Q.rows[q0 + t - 1]);
      }
      if (!sorted) {  // not expected; sorting keeps the result correct regardless
        tmp.clear();
        for (int64_t t = 0; t < len; ++t) tmp.emplace_back(Q.rows[q0 + t], Q.rowpos[q0 + t]);
        std::sort(tmp.begin(), tmp.end());
        for (int64_t t = 0; t < len; ++t) {
          Q.rows[q0 + t] = tmp[static_cast<size_t>(t)].first;
          Q.rowpos[q0 + t] = tmp[static_cast<size_t>(t)].second;
        }
      }
    }
  };
  // Each supernode's rows land at their final offsets: two threads take the
  // supernodes holding the first and the second half of the rows.
  const int32_t half = static_cast<int32_t>(
      std::lower_bound(Q.row_ptr.begin(), Q.row_ptr.end(), Q.row_ptr[R.ns] / 2) - Q.row_ptr.begin());
  if (two_threads && Q.row_ptr[R.ns] >= kSplitRows && half > 0 && half < R.ns) {
    tbb::parallel_invoke([&] { map_rows(0, half); }, [&] { map_rows(half, R.ns); });
  } else {
    map_rows(0, R.ns);
  }
  R = std::move(Q);
  return true;
}

void complete_structure(SymbolicFactor& S, bool two_threads) {
  const int32_t n = S.n, ns = S.ns;
  auto columns = [&] {
    S.super_etree_height = tree_height(S.super_parent);
    S.parent.assign(n, -1);
    S.col_count.assign(n, 0);
    S.super_value_ptr.assign(static_cast<size_t>(ns) + 1, 0);
    // Sums in locals, stored once: fields of S written in these loops shared a
    // cache line with the update lists' maximum, written by the other thread.
    int64_t nnz_exact = 0, nnz_L = 0;
    int32_t max_rows = 0;
    for (int32_t s = 0; s < ns; ++s) {
      const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
      const int64_t r = S.nrows(s), c = l - f;
      for (int32_t j = f; j < l; ++j) {
        S.col_count[j] = static_cast<int32_t>(r - (j - f));
        nnz_exact += S.col_count[j];
        if (j + 1 < l) S.parent[j] = j + 1;
        else if (r > c) S.parent[j] = S.super_rows[S.super_row_ptr[s] + c];
      }
      S.super_value_ptr[s + 1] = S.super_value_ptr[s] + r * c;
      nnz_L += r * c - c * (c - 1) / 2;
      max_rows = std::max<int32_t>(max_rows, static_cast<int32_t>(r));
    }
    S.nnz_exact = nnz_exact;
    S.nnz_L = nnz_L;
    S.max_super_rows = max_rows;
    S.etree_height = tree_height(S.parent);
  };
  // Update lists: (target, source) pairs in ascending source order, then a
  // stable counting sort by target. They read only the row structure, so they
  // are built beside the column pass.
  auto update_lists = [&] {
    std::vector<std::pair<int32_t, int32_t>> pairs;
    pairs.reserve(static_cast<size_t>(ns));
    int64_t max_entries = 0;
    for (int32_t d = 0; d < ns; ++d) {
      const int32_t* rd = S.super_rows.data() + S.super_row_ptr[d];
      const int64_t nr = S.nrows(d);
      int64_t t = S.ncols(d);
      while (t < nr) {
        const int32_t s = S.col_to_super[rd[t]];
        const int32_t send = S.super_first_col[s + 1];
        int64_t t2 = t + 1;
        while (t2 < nr && rd[t2] < send) ++t2;
        pairs.emplace_back(s, d);
        max_entries = std::max(max_entries, (nr - t) * (t2 - t));
        t = t2;
      }
    }
    S.max_update_entries = max_entries;
    S.update_ptr.assign(static_cast<size_t>(ns) + 1, 0);
    for (const auto& pr : pairs) ++S.update_ptr[pr.first + 1];
    for (int32_t s = 0; s < ns; ++s) S.update_ptr[s + 1] += S.update_ptr[s];
    S.update_from.resize(pairs.size());
    std::vector<int64_t> next(S.update_ptr.begin(), S.update_ptr.end() - 1);
    for (const auto& pr : pairs) S.update_from[next[pr.first]++] = pr.second;
  };
  if (two_threads && static_cast<int64_t>(S.super_rows.size()) >= kSplitRows) {
    tbb::parallel_invoke(columns, update_lists);
  } else {
    columns();
    update_lists();
  }
}

}  // namespace locus::update_detail
