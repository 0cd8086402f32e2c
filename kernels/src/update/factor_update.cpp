// Factor-once update of a supernodal factor to a principal submatrix
// (kernels/include/locus/kernels/update/factor_update.hpp; thesis §5.4–5.5, algorithm steps 1–6 of §5.5).
//
// Supernodal version of the column algorithm of the thesis:
//  - structure: global supernode s restricted to its columns in I is one
//    supernode of L' with rows rows(s) ∩ I. Closure holds because the global
//    structure is closed and restriction keeps every row ≥ first(s') of a
//    descendant inside rows(s) ∩ I. Its supernodal parent is the restricted
//    supernode holding its first off-diagonal row (not the global parent,
//    which may have no column in I).
//  - marking: the column etree of the restricted structure contains every
//    ancestor relation of the exact factor of A_II (its column patterns are
//    supersets), so walking it from the first I-row of each column of L_IB
//    reaches every changed column (§5.5). Per global supernode only one start
//    is needed: the first I-column after its first B-column, or, when its last
//    columns are all in B, its first I-row below — every other start it could
//    give is an ancestor of that one. The walk stops at marked columns.
//  - values: unmarked supernodes copy their restricted rows/columns of L (the
//    sharing form borrows instead those that keep all their global rows and
//    columns: their block is L's block); marked ones are recomputed by
//    factorize_supernodes from A_II and their descendants (copied, borrowed or
//    recomputed), BLAS-3, in parallel subtrees.
//
// Cost (prepared updater, the repeated-update case): nothing is O(n) or
// O(nnz(A)) per update except scans of n/64-word bit sets. I is sorted through
// bit sets; A_II and its assembly map are read from a copy of A stored in L's
// column order, where a patch's columns are a few contiguous ranges (nested
// dissection keeps subtrees together), not gathered from I's columns spread
// over A; the symbolic parts are derived in single passes over the restricted
// structure. A_II's extraction runs beside marking, copying and the
// recomputation, which assembles its supernodes from the same copy of A. With
// two threads the structure passes that handle many rows (restriction, the
// postorder's row remapping, the update lists) are also split in two, each
// half writing its own range, so the result is the same for any thread count;
// the second thread first-touches a large result's fresh pages while the first
// finishes the structure, and takes over part of the copy once A_II is done.
#include "locus/kernels/update/factor_update.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include "locus/core/bit_set.hpp"
#include "locus/kernels/symbolic/etree.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs f inside an arena of the context's thread budget (TBB owns the threads).
template <class F>
void in_arena(const RunContext& ctx, F&& f) {
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  if (threads <= 1) {
    f(1);
    return;
  }
  run_with_threads(threads, [&] { f(threads); });
}

// A_II from a local index (local(v) = position of v in I, -1 outside), which
// is increasing on I, so rows stay sorted and lower. One pass with an upper
// bound of the entries: the columns of a scattered I are cache misses, read once.
template <class Local>
CscMatrix submatrix_with(const CscMatrix& A, std::span<const int32_t> vertices, Local local) {
  const int32_t m = static_cast<int32_t>(vertices.size());
  int64_t bound = 0;
  for (const int32_t v : vertices) bound += A.colptr[v + 1] - A.colptr[v];
  CscMatrix B;
  B.nrows = B.ncols = m;
  B.colptr.resize(static_cast<size_t>(m) + 1);
  B.colptr[0] = 0;
  B.rowind.resize(static_cast<size_t>(bound));
  B.values.resize(static_cast<size_t>(bound));
  int64_t q = 0;
  for (int32_t a = 0; a < m; ++a) {
    const int32_t v = vertices[a];
    for (int64_t p = A.colptr[v]; p < A.colptr[v + 1]; ++p) {
      const int32_t r = local(A.rowind[p]);
      if (r >= 0) {
        B.rowind[q] = r;
        B.values[q] = A.values[p];
        ++q;
      }
    }
    B.colptr[a + 1] = q;
  }
  B.rowind.resize(static_cast<size_t>(q));
  B.values.resize(static_cast<size_t>(q));
  return B;
}

CscMatrix submatrix_from_map(const CscMatrix& A, std::span<const int32_t> vertices, const std::vector<int32_t>& local) {
  return submatrix_with(A, vertices, [&](int32_t v) { return local[v]; });
}

// The restricted supernodal structure, with the positions of its rows and
// columns inside the global supernodes (for copying values).
struct Restricted {
  int32_t ns = 0;
  std::vector<int32_t> gsuper;      // ns: global supernode it comes from
  std::vector<int32_t> first_col;   // ns + 1
  std::vector<int32_t> gcol;        // m: global factor column of each restricted column
  std::vector<int32_t> colpos;      // m: offset of that column inside its global supernode
  std::vector<int64_t> row_ptr;     // ns + 1
  std::vector<int32_t> rows;        // restricted column ids, ascending per supernode
  std::vector<int32_t> rowpos;      // position of each row in the global supernode's row list
  std::vector<int32_t> parent;      // ns
};

// First touches of a fresh factor's pages, done by the second thread while the
// first one finishes the structure (the value offsets need the whole
// restricted structure; its size is known once the supernodes are restricted).
// Only for results of at least FactorUpdateOptions::prefault_min_bytes (32 MB):
// glibc serves smaller blocks again from the heap, already mapped, while
// larger ones are always a fresh mapping whose every page faults, and the
// faults of two threads overlap (costs: docs/factor_update.md). Every value is
// written again later (copied or recomputed), so what this writes never shows;
// it stops before anything else writes the values.
class Prefault {
 public:
  Prefault(double* data, int64_t count, bool active) : data_(data), count_(count) {
    if (active) tg_.run([this] { run(); });
  }
  ~Prefault() { stop(); }
  void stop() {
    stop_.store(true, std::memory_order_relaxed);
    tg_.wait();
  }

 private:
  void run() {
    constexpr int64_t kPage = 4096 / sizeof(double), kChunk = 64 * kPage;  // a stop check per 256 KB
    for (int64_t c0 = 0; c0 < count_ && !stop_.load(std::memory_order_relaxed); c0 += kChunk) {
      const int64_t c1 = std::min(count_, c0 + kChunk);
      for (int64_t i = c0; i < c1; i += kPage) data_[i] = 0.0;
    }
  }
  double* data_;
  int64_t count_;
  std::atomic<bool> stop_{false};
  tbb::task_group tg_;
};

// A structure pass is split over two threads only when it handles at least
// this many rows: below, waking the second thread could cost what the half
// saves (not tuned; docs/factor_update.md).
constexpr int64_t kSplitRows = int64_t{1} << 14;

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

// Renumbers the restricted supernodes in postorder of their tree (children in
// ascending order, so an order that is already a postorder is kept). Needed
// when I splits a global subtree: a restricted node can then become a root (or
// hang elsewhere) in the middle of another node's range, and the parallel
// factorization relies on contiguous subtrees.
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

// The parts of the restricted symbolic factor that do not involve A (what
// complete_symbolic derives, in single passes): value offsets, column etree and
// counts, heights, workspace sizes and the update lists (for each s, the
// supernodes d < s with a row in s's columns, ascending).
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

// Error(Numerical) for a non-finite entry of A_II. A type of its own so that
// the recomputation, whose assembler may raise it, passes it on unchanged
// instead of renaming it as a pivot failure; update() hands it to the caller
// as a plain Error.
class NotFiniteEntry : public Error {
 public:
  using Error::Error;
};

// A non-finite entry of A_II, named by its vertices (local indices a and b,
// in A's numbering or the caller's ids): a NaN or infinity would pass the
// pivots silently and poison every solve.
[[noreturn]] void fail_not_finite(std::span<const int32_t> vertices, std::span<const int32_t> ids, int32_t a, int32_t b) {
  auto nm = [&](int32_t x) { return std::to_string(ids.empty() ? vertices[x] : ids[vertices[x]]); };
  throw NotFiniteEntry(ErrorCode::Numerical, "submatrix entry of vertices " + nm(a) + " and " + nm(b) + " is not finite");
}

// A_II (lower CSC, local numbering) and the assembly map of the restricted
// factor Sp, read from A stored in L's column order (ap: column c = rows r >= c).
// The columns of a patch are a few contiguous ranges of L's order, so this
// reads A with the factor's locality. gcol: restricted column -> L's column;
// col_new: L's column -> restricted column (-1 outside I). The entries are
// visited supernode by supernode (which groups the assembly map), then put in
// A_II's column order, rows ascending, by two stable counting sorts.
void assemble_from_factor_order(SymbolicFactor& Sp, const std::vector<int32_t>& gcol, const std::vector<int32_t>& col_new,
                                const std::vector<int64_t>& ap_ptr, const std::vector<int32_t>& ap_row,
                                const std::vector<double>& ap_val, const std::vector<int32_t>& vertices,
                                std::span<const int32_t> ids, CscMatrix& B) {
  const int32_t m = Sp.n, ns = Sp.ns;
  int64_t bound = 0;
  for (int32_t c = 0; c < m; ++c) bound += ap_ptr[gcol[c] + 1] - ap_ptr[gcol[c]];
  // One record per entry (local column and row, row >= column, and value):
  // the sort by column below fetches an entry with one cache miss, not three.
  // Scratch arrays are left uninitialized: every slot read is written first.
  struct Entry {
    int32_t col, row;
    double val;
  };
  std::vector<Entry, DefaultInitAllocator<Entry>> e(static_cast<size_t>(bound));
  Sp.a_super_ptr.assign(static_cast<size_t>(ns) + 1, 0);
  Sp.a_dst.resize(static_cast<size_t>(bound));
  std::vector<int32_t> rowpos(m);
  bool finite = true;
  int64_t k = 0;
  for (int32_t s = 0; s < ns; ++s) {
    const int32_t f = Sp.super_first_col[s], l = Sp.super_first_col[s + 1], nr = Sp.nrows(s);
    const int32_t* rows = Sp.super_rows.data() + Sp.super_row_ptr[s];
    for (int32_t t = 0; t < nr; ++t) rowpos[rows[t]] = t;
    for (int32_t c = f; c < l; ++c) {
      const int32_t gc = gcol[c], b = Sp.perm[c];
      const int64_t col_off = Sp.super_value_ptr[s] + static_cast<int64_t>(c - f) * nr;
      for (int64_t p = ap_ptr[gc]; p < ap_ptr[gc + 1]; ++p) {
        const int32_t r = col_new[ap_row[p]];
        if (r < 0) continue;
        const int32_t t = rowpos[r];
        if (r < c || t < 0 || t >= nr || rows[t] != r)
          fail(ErrorCode::Internal, "factor update: restricted structure misses entry (" + std::to_string(r) + ", " +
                                        std::to_string(c) + ") of the submatrix");
        const int32_t a = Sp.perm[r];
        const double v = ap_val[p];
        Sp.a_dst[static_cast<size_t>(k)] = col_off + t;
        e[static_cast<size_t>(k)] = Entry{std::min(a, b), std::max(a, b), v};
        finite = finite && std::isfinite(v);
        ++k;
      }
    }
    Sp.a_super_ptr[s + 1] = k;
  }
  Sp.a_dst.resize(static_cast<size_t>(k));
  if (!finite)
    for (int64_t q = 0; q < k; ++q)
      if (!std::isfinite(e[q].val)) fail_not_finite(vertices, ids, e[q].row, e[q].col);
  // A_II's columns, rows ascending: a counting sort by row, then a stable one
  // by column; a_src follows the entries.
  std::vector<int32_t, DefaultInitAllocator<int32_t>> by_row(static_cast<size_t>(k));
  {
    std::vector<int32_t> cnt(static_cast<size_t>(m) + 1, 0);
    for (int64_t q = 0; q < k; ++q) ++cnt[e[q].row + 1];
    for (int32_t a = 0; a < m; ++a) cnt[a + 1] += cnt[a];
    for (int64_t q = 0; q < k; ++q) by_row[cnt[e[q].row]++] = static_cast<int32_t>(q);
  }
  B.nrows = B.ncols = m;
  B.colptr.assign(static_cast<size_t>(m) + 1, 0);
  for (int64_t q = 0; q < k; ++q) ++B.colptr[e[q].col + 1];
  for (int32_t a = 0; a < m; ++a) B.colptr[a + 1] += B.colptr[a];
  B.rowind.resize(static_cast<size_t>(k));
  B.values.resize(static_cast<size_t>(k));
  Sp.a_src.resize(static_cast<size_t>(k));
  std::vector<int64_t> next(B.colptr.begin(), B.colptr.end() - 1);
  for (const int32_t q : by_row) {
    const Entry& x = e[q];
    const int64_t dst = next[x.col]++;
    B.rowind[dst] = x.row;
    B.values[dst] = x.val;
    Sp.a_src[q] = dst;
  }
  Sp.a_nnz = k;
  Sp.a_pattern_hash = pattern_hash(B);
}

// Re-raises a not-positive-definite error of the submatrix factorization with
// the vertex named in A's numbering (or the caller's ids), not the local one.
[[noreturn]] void rethrow_numerical(const Error& e, const SymbolicFactor& Sp, std::span<const int32_t> vertices,
                                    std::span<const int32_t> ids) {
  const std::string msg = e.what();
  const int64_t col = e.where().column;
  if (col >= 0 && col < Sp.n) {
    const int32_t local = Sp.perm[static_cast<size_t>(col)];
    const int32_t v = vertices[local];
    const int32_t name = ids.empty() ? v : ids[v];
    fail(ErrorCode::Numerical,
         "submatrix is not positive definite at vertex " + std::to_string(name) + " (submatrix index " +
             std::to_string(local) + ", factor column " + std::to_string(col) + ")",
         ErrorLocation{name, col});
  }
  fail(ErrorCode::Numerical, std::string("submatrix: ") + msg);
}

}  // namespace

CscMatrix principal_submatrix(const CscMatrix& A, std::span<const int32_t> vertices) {
  const int32_t n = A.ncols;
  std::vector<int32_t> local(n, -1);
  int32_t prev = -1;
  for (size_t a = 0; a < vertices.size(); ++a) {
    const int32_t v = vertices[a];
    if (v < 0 || v >= n || v <= prev)
      fail(ErrorCode::BadUsage, "principal_submatrix: indices must be sorted, unique and in [0, " + std::to_string(n) +
                                    "); entry " + std::to_string(a) + " is " + std::to_string(v));
    local[v] = static_cast<int32_t>(a);
    prev = v;
  }
  return submatrix_from_map(A, vertices, local);
}

Ordering factor_ordering(const SymbolicFactor& S) { return Ordering{std::vector<int32_t>(S.perm), std::vector<int32_t>(S.iperm)}; }

namespace {
const NumericFactor& factor_of(const std::shared_ptr<const NumericFactor>& L) {
  if (!L) fail(ErrorCode::BadUsage, "update_factor: no factor (null pointer)");
  return *L;
}
}  // namespace

FactorUpdater::FactorUpdater(std::shared_ptr<const NumericFactor> L, const CscMatrix& A,
                             const FactorUpdateOptions& opt, bool index_rows)
    : FactorUpdater(factor_of(L), A, opt, index_rows) {
  lender_ = std::move(L);
}

FactorUpdater::FactorUpdater(const NumericFactor& L, const CscMatrix& A, const FactorUpdateOptions& opt,
                             bool index_rows)
    : L_(L), A_(A), opt_(opt) {
  if (!L.symbolic) fail(ErrorCode::BadUsage, "update_factor: factor has no symbolic part");
  const SymbolicFactor& S = *L.symbolic;
  const int32_t n = S.n;
  if (A.ncols != n || A.nrows != n || A.nnz() != S.a_nnz || pattern_hash(A) != S.a_pattern_hash)
    fail(ErrorCode::BadUsage, "update_factor: matrix does not have the sparsity pattern the factor was built for");
  if (!storage_matches_symbolic(L))
    fail(ErrorCode::BadUsage, "update_factor: factor values are not sized to its symbolic factor");
  if (!opt.vertex_ids.empty() && static_cast<int32_t>(opt.vertex_ids.size()) != n)
    fail(ErrorCode::BadUsage, "update_factor: vertex_ids has " + std::to_string(opt.vertex_ids.size()) +
                                  " entries for a matrix of " + std::to_string(n) + " columns");
  local_.assign(n, -1);
  col_new_.assign(n, -1);
  in_super_.assign(S.ns, 0);
  vbits_.assign((static_cast<size_t>(n) + 63) / 64, 0);
  vrank_.assign(vbits_.size(), 0);
  cbits_.assign(vbits_.size(), 0);
  if (!index_rows) return;
  // A in factor numbering, lower: each entry goes to column min(iperm) (counting sort).
  ap_ptr_.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) ++ap_ptr_[std::min(S.iperm[A.rowind[p]], S.iperm[j]) + 1];
  for (int32_t c = 0; c < n; ++c) ap_ptr_[c + 1] += ap_ptr_[c];
  ap_row_.resize(static_cast<size_t>(ap_ptr_[n]));
  ap_val_.resize(static_cast<size_t>(ap_ptr_[n]));
  {
    std::vector<int64_t> next(ap_ptr_.begin(), ap_ptr_.end() - 1);
    for (int32_t j = 0; j < n; ++j)
      for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
        const int32_t a = S.iperm[A.rowind[p]], b = S.iperm[j];
        const int64_t q = next[std::min(a, b)]++;
        ap_row_[q] = std::max(a, b);
        ap_val_[q] = A.values[p];
      }
  }
  // Row -> supernodes holding it below their diagonal block (the transpose of
  // the supernodal row structure), for marking from the I side.
  below_ptr_.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t d = 0; d < S.ns; ++d)
    for (int64_t t = S.super_row_ptr[d] + S.ncols(d); t < S.super_row_ptr[d + 1]; ++t) ++below_ptr_[S.super_rows[t] + 1];
  for (int32_t r = 0; r < n; ++r) below_ptr_[r + 1] += below_ptr_[r];
  below_super_.resize(static_cast<size_t>(below_ptr_[n]));
  std::vector<int64_t> next(below_ptr_.begin(), below_ptr_.end() - 1);
  for (int32_t d = 0; d < S.ns; ++d)
    for (int64_t t = S.super_row_ptr[d] + S.ncols(d); t < S.super_row_ptr[d + 1]; ++t) below_super_[next[S.super_rows[t]]++] = d;
}

FactorUpdate update_factor(const NumericFactor& L, const CscMatrix& A, std::span<const int32_t> I,
                           const RunContext& ctx, const FactorUpdateOptions& opt) {
  return FactorUpdater(L, A, opt, /*index_rows=*/false).update(I, ctx);
}

FactorUpdate FactorUpdater::update(std::span<const int32_t> I, const RunContext& ctx) {
  // With the prepared updater and two or more threads the structure phase
  // splits its passes too: run the whole update in the arena once instead of
  // entering it for every parallel step.
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  try {
    if (threads < 2 || ap_ptr_.empty()) return update_impl(I, ctx, false);
    FactorUpdate out;
    run_with_threads(threads, [&] { out = update_impl(I, ctx, true); });
    return out;
  } catch (const NotFiniteEntry& e) {
    throw Error(e);  // callers see the library's one exception type
  }
}

// One call of update(I). The steps hand each other the result being built, I's
// factor columns, the restricted structure and the marks; they run in the order
// update_impl lists. The destructor leaves the updater's maps all -1 / 0 again
// however the call ends (a refused set, a failed pivot, a cancellation).
struct FactorUpdater::Call {
  using clock = std::chrono::steady_clock;

  Call(FactorUpdater& updater, std::span<const int32_t> set, const RunContext& context, bool two)
      : u(updater), L(updater.L_), S(*updater.L_.symbolic), opt(updater.opt_), I(set), ctx(context),
        two_threads(two), prepared(!updater.ap_ptr_.empty()), borrow(updater.lender_ != nullptr) {}
  Call(const Call&) = delete;
  Call& operator=(const Call&) = delete;
  ~Call();

  void plan();
  void copy_whole();
  void list_factor_columns();
  void refactor_fresh();
  void restrict_to_set();
  std::shared_ptr<SymbolicFactor> restricted_symbolic();
  void finish_prepared();
  void finish_one_shot();
  void mark_and_copy();
  void mark_changed();
  void walk(int32_t c);
  void count_marked();
  void lay_out_borrowed();
  void copy_unmarked();
  void copy_supernodes(int32_t s0, int32_t s1);
  void extract_submatrix();
  void assemble_direct(int32_t s, int32_t c0, int32_t c1, double* block, const int32_t* rowmap) const;
  void refactor_marked(const SupernodeAssembler* direct);
  template <class Factorize>
  void factor_naming_vertices(const SymbolicFactor& Sf, Factorize&& run);
  int32_t local_of(int32_t v) const;

  FactorUpdater& u;
  const NumericFactor& L;
  const SymbolicFactor& S;  // L's
  const FactorUpdateOptions& opt;
  const std::span<const int32_t> I;
  const RunContext& ctx;
  const bool two_threads;  // see update_impl
  const bool prepared;     // index_rows: row index and A in factor order
  const bool borrow;       // sharing form
  const clock::time_point t0 = clock::now();
  FactorUpdate out;
  FactorUpdateStats& st = out.stats;
  int32_t m = 0;              // |I|
  std::vector<int32_t> gcol;  // I's factor columns, ascending
  bool cbits_clear = false;   // cbits_ cleared from gcol already (sequential, unlike iperm of I)
  bool maps_filled = false;   // col_new_ and in_super_ were set for gcol
  Restricted R;                         // the restricted structure, with positions in L's blocks
  std::shared_ptr<SymbolicFactor> Sp;   // the result's symbolic factor
  std::vector<uint8_t> cmark, smark;    // marked columns / supernodes of Sp
};

FactorUpdater::Call::~Call() {
  const int32_t n = static_cast<int32_t>(u.local_.size());
  for (const int32_t v : I)
    if (v >= 0 && v < n) {
      if (!prepared) u.local_[v] = -1;  // only the one-shot path fills the map
      u.vbits_[static_cast<size_t>(v) >> 6] = 0;
      if (!cbits_clear) u.cbits_[static_cast<size_t>(S.iperm[v]) >> 6] = 0;
    }
  if (maps_filled)
    for (const int32_t c : gcol) {
      u.col_new_[c] = -1;
      u.in_super_[S.col_to_super[c]] = 0;
    }
}

FactorUpdate FactorUpdater::update_impl(std::span<const int32_t> I, const RunContext& ctx, bool two_threads) {
  if (I.empty()) fail(ErrorCode::BadUsage, "update_factor: the vertex set is empty");
  Call call(*this, I, ctx, two_threads);
  call.plan();
  if (call.m == L_.symbolic->n) {
    call.copy_whole();
  } else {
    call.list_factor_columns();
    if (call.st.touched_share < opt_.refactor_below_share) {
      call.refactor_fresh();
    } else {
      call.restrict_to_set();
      if (call.prepared) call.finish_prepared();
      else call.finish_one_shot();
    }
  }
  return std::move(call.out);
}

// Local index of a vertex of I = its rank in the bit set: a popcount over a
// prefix table of n/64 entries, which stays in cache where the n-sized map
// (random in vertex order) does not. The gather of A_II from A (one-shot
// path) still uses the map.
int32_t FactorUpdater::Call::local_of(int32_t v) const {
  const size_t wi = static_cast<size_t>(v) >> 6;
  return u.vrank_[wi] + std::popcount(u.vbits_[wi] & ((uint64_t{1} << (v & 63)) - 1));
}

// Runs a factorization of A_II. A numerical failure (a pivot) is re-raised
// naming the vertex in A's numbering; a non-finite entry (NotFiniteEntry, from
// the direct assembler) names its vertices already and passes unchanged.
template <class Factorize>
void FactorUpdater::Call::factor_naming_vertices(const SymbolicFactor& Sf, Factorize&& run) {
  try {
    run();
  } catch (const NotFiniteEntry&) {
    throw;
  } catch (const Error& e) {
    if (e.code() != ErrorCode::Numerical) throw;
    rethrow_numerical(e, Sf, out.vertices, opt.vertex_ids);
  }
}

// Checks I and sorts it, with its factor columns, through bit sets: O(m + n/64).
void FactorUpdater::Call::plan() {
  const int32_t n = S.n;
  auto name = [&](int32_t v) { return std::to_string(opt.vertex_ids.empty() ? v : opt.vertex_ids[v]); };
  for (size_t a = 0; a < I.size(); ++a) {
    const int32_t v = I[a];
    if (v < 0 || v >= n)
      fail(ErrorCode::BadUsage, "update_factor: vertex " + std::to_string(v) + " (entry " + std::to_string(a) +
                                    ") is out of range [0, " + std::to_string(n) + ")");
    uint64_t& w = u.vbits_[static_cast<size_t>(v) >> 6];
    const uint64_t bit = uint64_t{1} << (v & 63);
    if (w & bit) fail(ErrorCode::BadUsage, "update_factor: vertex " + name(v) + " appears twice in the set");
    w |= bit;
  }
  m = static_cast<int32_t>(I.size());
  out.vertices.reserve(m);
  append_set_bits(u.vbits_, out.vertices);
  // Factor columns from the sorted vertices: iperm is then read in ascending
  // order (prefetchable) instead of in I's order (a cache miss per vertex).
  for (const int32_t v : out.vertices) u.cbits_[static_cast<size_t>(S.iperm[v]) >> 6] |= uint64_t{1} << (S.iperm[v] & 63);
  for (size_t wi = 0, r = 0; wi < u.vbits_.size(); ++wi) {  // the rank table of local_of
    u.vrank_[wi] = static_cast<int32_t>(r);
    r += static_cast<size_t>(std::popcount(u.vbits_[wi]));
  }
  if (!prepared)
    for (int32_t a = 0; a < m; ++a) u.local_[out.vertices[a]] = a;
  st.n = n;
  st.n_sub = m;
}

// I = all indices: nothing is removed, L is the factor (same numbering).
void FactorUpdater::Call::copy_whole() {
  out.A_sub = u.A_;
  st.supernodes = S.ns;
  st.values_stored = S.super_value_ptr[S.ns];
  if (borrow) {  // every block is borrowed
    out.factor.symbolic = L.symbolic;
    out.factor.borrowed.resize(S.ns);
    for (int32_t s = 0; s < S.ns; ++s) out.factor.borrowed[s] = L.block(s);
    out.factor.own_offset.assign(S.ns, -1);
    out.factor.lender = u.lender_;
    st.values_borrowed = st.values_stored;
  } else {
    out.factor = L;  // (with its borrowed blocks and their lender, if L borrows)
  }
  st.nnz_stored = S.nnz_L;
  st.copied_whole = true;
  st.copy_s = seconds_since(t0);
}

// I's factor columns, ascending (gcol), and the share of the columns of the
// global supernodes holding them that I keeps (which chooses the fresh path).
void FactorUpdater::Call::list_factor_columns() {
  gcol.reserve(m);
  append_set_bits(u.cbits_, gcol);
  for (const int32_t c : gcol) u.cbits_[static_cast<size_t>(c) >> 6] = 0;
  cbits_clear = true;
  int64_t touched = 0;  // columns of the global supernodes that hold I's columns
  for (int32_t c = 0, prev = -1; c < m; ++c) {
    const int32_t s = S.col_to_super[gcol[c]];
    if (s != prev) touched += S.ncols(s);
    prev = s;
  }
  st.touched_share = static_cast<double>(m) / static_cast<double>(touched);
}

// A scattered set (touched_share below refactor_below_share): A_II analysed and
// factored from scratch, in L's relative order (I's factor columns ascending).
// Membership and rank come from the bit set (n/64 words, in cache), not the
// n-sized map; the column map and per-supernode counts are never filled.
void FactorUpdater::Call::refactor_fresh() {
  out.A_sub = submatrix_with(u.A_, out.vertices, [&](int32_t v) {
    return (u.vbits_[static_cast<size_t>(v) >> 6] >> (v & 63)) & 1 ? local_of(v) : -1;
  });
  for (int32_t a = 0; a < m; ++a)
    for (int64_t p = out.A_sub.colptr[a]; p < out.A_sub.colptr[a + 1]; ++p)
      if (!std::isfinite(out.A_sub.values[p])) fail_not_finite(out.vertices, opt.vertex_ids, out.A_sub.rowind[p], a);
  Ordering order;
  order.perm.resize(m);
  order.iperm.resize(m);
  for (int32_t c = 0; c < m; ++c) {
    order.perm[c] = local_of(S.perm[gcol[c]]);
    order.iperm[order.perm[c]] = c;
  }
  auto Sx = analyze(out.A_sub, order);
  st.structure_s = seconds_since(t0);
  const auto t3 = clock::now();
  factor_naming_vertices(*Sx, [&] { out.factor = factorize(Sx, out.A_sub, ctx); });
  st.factor_s = seconds_since(t3);
  st.refactored = true;
  st.supernodes = st.supernodes_recomputed = Sx->ns;
  st.columns_marked = st.columns_recomputed = m;
  st.columns_updated_fraction = 1.0;
  st.values_stored = st.values_recomputed = Sx->super_value_ptr[Sx->ns];
  st.nnz_stored = Sx->nnz_L;
  st.flops_recomputed = Sx->flops();
}

// (1) The restricted structure in L's order (then postordered if needed), the
// result's storage and its symbolic factor; the one-shot path also gathers
// A_II here (the prepared one extracts it beside the later steps).
void FactorUpdater::Call::restrict_to_set() {
  std::vector<int32_t>& col_new = u.col_new_;
  maps_filled = true;
  for (int32_t c = 0; c < m; ++c) {
    col_new[gcol[c]] = c;
    ++u.in_super_[S.col_to_super[gcol[c]]];
  }
  R = restrict_structure(S, col_new, gcol, two_threads);
  int64_t values_total = 0;
  for (int32_t s = 0; s < R.ns; ++s)
    values_total += (R.row_ptr[s + 1] - R.row_ptr[s]) * (R.first_col[s + 1] - R.first_col[s]);
  // The result's storage, sized once: the postorder below permutes the
  // supernodes but keeps their total. Not initialized (DefaultInitAllocator).
  // A borrowing update sizes its own blocks after marking instead.
  if (!borrow) out.factor.values.resize(static_cast<size_t>(values_total));
  Prefault prefault(out.factor.values.data(), values_total,
                    !borrow && two_threads &&
                        values_total * static_cast<int64_t>(sizeof(double)) >= opt.prefault_min_bytes);
  st.reordered = postorder_in_place(R, two_threads);
  if (st.reordered)
    for (int32_t c = 0; c < m; ++c) col_new[R.gcol[c]] = c;
  Sp = restricted_symbolic();
  if (prepared) {
    complete_structure(*Sp, two_threads);  // A_II and its assembly map come later, beside marking and copying
  } else {
    out.A_sub = submatrix_from_map(u.A_, out.vertices, u.local_);
    complete_symbolic(*Sp, out.A_sub);  // value offsets, assembly map, update lists, column etree
  }
  st.supernodes = Sp->ns;
  st.nnz_stored = Sp->nnz_L;
  st.values_stored = Sp->super_value_ptr[Sp->ns];
  st.structure_s = seconds_since(t0);
  ctx.check_cancel();
  prefault.stop();  // before anything else writes the values
}

// The symbolic factor of A_II from R: perm in local indices, supernodes, rows
// (moved out of R, which keeps row_ptr and rowpos for the copy).
std::shared_ptr<SymbolicFactor> FactorUpdater::Call::restricted_symbolic() {
  auto F = std::make_shared<SymbolicFactor>();
  F->n = m;
  F->perm.resize(m);
  F->iperm.resize(m);
  for (int32_t c = 0; c < m; ++c) {
    F->perm[c] = local_of(S.perm[R.gcol[c]]);
    F->iperm[F->perm[c]] = c;
  }
  F->ns = R.ns;
  F->super_first_col = R.first_col;
  F->col_to_super.resize(m);
  for (int32_t s = 0; s < R.ns; ++s)
    for (int32_t c = R.first_col[s]; c < R.first_col[s + 1]; ++c) F->col_to_super[c] = s;
  F->super_parent = R.parent;
  F->super_row_ptr = R.row_ptr;
  F->super_rows = std::move(R.rows);
  return F;
}

// Prepared updater: marking, copying and the recomputation do not read A_II,
// so they run beside its extraction (independent outputs: the result does not
// depend on the threads). The recomputed supernodes are assembled straight
// from the copy of A in factor order (the entries A_II's map would place), so
// that they need not wait for A_II.
void FactorUpdater::Call::finish_prepared() {
  const SupernodeAssembler direct = [this](int32_t s, int32_t c0, int32_t c1, double* block, const int32_t* rowmap) {
    assemble_direct(s, c0, c1, block, rowmap);
  };
  auto mark_copy_factor = [&] {
    mark_and_copy();
    refactor_marked(&direct);
  };
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  if (threads >= 2) {
    in_arena(ctx, [&](int) { tbb::parallel_invoke([&] { extract_submatrix(); }, mark_copy_factor); });
  } else {
    mark_copy_factor();
    extract_submatrix();
  }
}

// One-shot updater: A_II was gathered with the structure.
void FactorUpdater::Call::finish_one_shot() {
  mark_and_copy();
  ctx.check_cancel();
  refactor_marked(nullptr);
}

// (2) marking, then (3) each unmarked supernode copied from L or borrowed.
void FactorUpdater::Call::mark_and_copy() {
  const auto t1 = clock::now();
  mark_changed();
  count_marked();
  out.factor.symbolic = Sp;
  if (borrow) lay_out_borrowed();
  st.mark_s = seconds_since(t1);
  ctx.check_cancel();
  const auto t2 = clock::now();
  copy_unmarked();
  st.copy_s = seconds_since(t2);
}

// Marks the etree path from restricted column c up to the first marked column.
void FactorUpdater::Call::walk(int32_t c) {
  for (; c >= 0 && !cmark[c]; c = Sp->parent[c]) {
    cmark[c] = 1;
    ++st.columns_marked;
    smark[Sp->col_to_super[c]] = 1;
  }
}

// (2) Marking (§5.5): the changed columns are the ancestors, in the restricted
// etree, of the first I-row of every column of L_IB. All I-rows of a column lie
// on one etree path, so starting from every I-row of a B column marks the same
// set, and those rows are found from the I side in time that depends on I: an I
// column is such a row when a B column precedes it in its own supernode, or
// when a supernode with a B column has it among its rows below the diagonal
// block (below_super_ lists those per row).
void FactorUpdater::Call::mark_changed() {
  const std::vector<int32_t>& col_new = u.col_new_;
  cmark.assign(m, 0);
  smark.assign(Sp->ns, 0);
  for (size_t q = 0; q < gcol.size();) {
    const int32_t s = S.col_to_super[gcol[q]];
    const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
    size_t q2 = q;
    while (q2 < gcol.size() && gcol[q2] < l) ++q2;
    for (size_t t = q; t < q2; ++t)
      if (gcol[t] - f > static_cast<int32_t>(t - q)) {  // fewer I columns than positions before it: a B column
        walk(col_new[gcol[t]]);
        break;  // the later columns of s are its ancestors
      }
    q = q2;
  }
  if (u.below_ptr_.empty()) {
    // Without the row index (one-shot updates): scan the rows of every global
    // supernode with a B column for its first I-row — O(structure of L), still
    // cheaper than building the index for a single update.
    for (int32_t s = 0; s < S.ns; ++s) {
      if (u.in_super_[s] == S.ncols(s)) continue;  // no column of s is in B
      const int64_t r0 = S.super_row_ptr[s] + S.ncols(s);
      for (int64_t t = r0; t < S.super_row_ptr[s + 1]; ++t)
        if (col_new[S.super_rows[t]] >= 0) {
          walk(col_new[S.super_rows[t]]);
          break;  // its later I-rows are ancestors of this one
        }
    }
  }
  for (const int32_t c : gcol) {
    if (u.below_ptr_.empty() || cmark[col_new[c]]) continue;
    for (int64_t p = u.below_ptr_[c]; p < u.below_ptr_[c + 1]; ++p) {
      const int32_t d = u.below_super_[p];
      if (u.in_super_[d] < S.ncols(d)) {
        walk(col_new[c]);
        break;
      }
    }
  }
}

// The work the marks imply (FactorUpdateStats).
void FactorUpdater::Call::count_marked() {
  for (int32_t s = 0; s < Sp->ns; ++s)
    if (smark[s]) {
      ++st.supernodes_recomputed;
      st.columns_recomputed += Sp->ncols(s);
      st.values_recomputed += Sp->super_value_ptr[s + 1] - Sp->super_value_ptr[s];
      st.flops_recomputed += Sp->flops(s);
    }
  st.columns_updated_fraction = static_cast<double>(st.columns_recomputed) / m;
}

// Sharing form: an unmarked supernode that keeps every row and column of its
// global supernode has exactly that block (same rows, same order, same values):
// borrow it. The others (recomputed, or restricted) are own blocks.
void FactorUpdater::Call::lay_out_borrowed() {
  NumericFactor& F = out.factor;
  F.borrowed.assign(Sp->ns, nullptr);
  F.own_offset.assign(Sp->ns, -1);
  int64_t own = 0;
  for (int32_t s = 0; s < Sp->ns; ++s) {
    const int32_t gs = R.gsuper[s];
    const int64_t size = Sp->super_value_ptr[s + 1] - Sp->super_value_ptr[s];
    if (!smark[s] && Sp->ncols(s) == S.ncols(gs) && Sp->nrows(s) == S.nrows(gs)) {
      F.borrowed[s] = L.block(gs);
      st.values_borrowed += size;
    } else {
      F.own_offset[s] = own;
      own += size;
    }
  }
  F.values.resize(static_cast<size_t>(own));
  F.lender = u.lender_;
}

// (3) Copies the unmarked, not borrowed supernodes' restricted blocks from L.
// Threads only pay off for large copies (a gather, memory-bound), except in the
// prepared two-thread update: there the other thread extracts A_II meanwhile
// and takes over part of the copy once it is done (work stealing; each
// supernode is copied by one thread, so the result is the same).
void FactorUpdater::Call::copy_unmarked() {
  const int64_t copied = st.values_stored - st.values_recomputed - st.values_borrowed;
  const bool steal = two_threads && copied >= (int64_t{1} << 16);
  if (!steal && copied < (int64_t{1} << 22)) {
    copy_supernodes(0, Sp->ns);
  } else {
    in_arena(ctx, [&](int) {
      tbb::parallel_for(tbb::blocked_range<int32_t>(0, Sp->ns, 64),
                        [&](const tbb::blocked_range<int32_t>& rg) { copy_supernodes(rg.begin(), rg.end()); });
    });
  }
}

void FactorUpdater::Call::copy_supernodes(int32_t s0, int32_t s1) {
  NumericFactor& F = out.factor;
  for (int32_t s = s0; s < s1; ++s) {
    if (smark[s] || (borrow && F.borrowed[s])) continue;
    const int32_t gs = R.gsuper[s];
    const int64_t gm = S.nrows(gs);
    const double* src = L.block(gs);
    double* dst = F.block(s);
    const int32_t k = Sp->ncols(s), mr = Sp->nrows(s), f = Sp->super_first_col[s];
    const int32_t* rp = R.rowpos.data() + R.row_ptr[s];
    // Kept rows that are one run of the global rows (a supernode inside the
    // patch) are copied as runs, the others gathered.
    const bool run = rp[mr - 1] - rp[0] == mr - 1;
    for (int32_t j = 0; j < k; ++j) {
      const double* sc = src + static_cast<int64_t>(R.colpos[f + j]) * gm;
      double* dc = dst + static_cast<int64_t>(j) * mr;
      for (int32_t t = 0; t < j; ++t) dc[t] = 0.0;  // unused upper triangle, kept defined
      if (run) {
        const double* sr = sc + rp[0];
        for (int32_t t = j; t < mr; ++t) dc[t] = sr[t];
      } else {
        for (int32_t t = j; t < mr; ++t) dc[t] = sc[rp[t]];
      }
    }
  }
}

// Prepared updater: A_II and its assembly map (FactorUpdateOptions::submatrix).
void FactorUpdater::Call::extract_submatrix() {
  if (!opt.submatrix) return;
  const auto ta = clock::now();
  assemble_from_factor_order(*Sp, R.gcol, u.col_new_, u.ap_ptr_, u.ap_row_, u.ap_val_, out.vertices, opt.vertex_ids,
                             out.A_sub);
  st.assemble_s = seconds_since(ta);
  st.structure_s += st.assemble_s;
}

// Prepared updater: columns [c0, c1) of marked supernode s assembled from the
// copy of A in factor order (a SupernodeAssembler).
void FactorUpdater::Call::assemble_direct(int32_t s, int32_t c0, int32_t c1, double* block,
                                          const int32_t* rowmap) const {
  const int32_t f = Sp->super_first_col[s], nr = Sp->nrows(s);
  for (int32_t c = f + c0; c < f + c1; ++c) {
    const int32_t gc = R.gcol[c];
    double* col = block + static_cast<int64_t>(c - f) * nr;
    for (int64_t p = u.ap_ptr_[gc]; p < u.ap_ptr_[gc + 1]; ++p) {
      const int32_t r = u.col_new_[u.ap_row_[p]];
      if (r < 0) continue;
      const double v = u.ap_val_[p];
      if (!std::isfinite(v)) {  // as A_II's extraction reports it (whichever comes first)
        const int32_t a = Sp->perm[r], b = Sp->perm[c];
        fail_not_finite(out.vertices, opt.vertex_ids, std::max(a, b), std::min(a, b));
      }
      col[rowmap[r]] = v;
    }
  }
}

// (4) Recomputes the marked supernodes (left-looking, skipping the others),
// assembled by `direct` (prepared) or from A_II (one-shot).
void FactorUpdater::Call::refactor_marked(const SupernodeAssembler* direct) {
  const auto t3 = clock::now();
  if (st.supernodes_recomputed > 0)
    factor_naming_vertices(*Sp, [&] {
      if (direct) factorize_supernodes_assembled(out.factor, smark, *direct, ctx);
      else factorize_supernodes(out.factor, out.A_sub, smark, ctx);
    });
  st.factor_s = seconds_since(t3);
}

}  // namespace locus
