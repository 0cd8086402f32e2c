// Assembly map A -> L (kernels/include/locus/kernels/symbolic/assembly_map.hpp).
#include "locus/kernels/symbolic/assembly_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

struct Entry {
  int64_t src;
  int32_t row, col;
};

struct Workspace {
  HostVector<int32_t> rowpos;  // row -> local index in the current supernode (stale elsewhere)
  HostVector<Entry> entries, column, merged;  // a supernode's entries, one column's, merge buffer
};

void map_supernode(SymbolicFactor& S, const HalfGraph& g, int32_t s, Workspace& w) {
  const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1], nr = S.nrows(s);
  const int32_t* rows = S.super_rows.data() + S.super_row_ptr[s];
  for (int32_t t = 0; t < nr; ++t) w.rowpos[rows[t]] = t;
  // Each column's list is ascending in src (the graph keeps A's order); its
  // diagonal goes in at its place, and the columns are merged one by one.
  const auto by_src = [](const Entry& a, const Entry& b) { return a.src < b.src; };
  w.entries.clear();
  for (int32_t c = f; c < l; ++c) {
    HostVector<Entry>& col = c == f ? w.entries : w.column;
    col.clear();
    const int64_t d = g.diag[c];
    int64_t q = g.ptr[c];
    for (; q < g.ptr[c + 1] && g.src[q] < d; ++q) col.push_back({g.src[q], g.idx[q], c});
    if (d >= 0) col.push_back({d, c, c});
    for (; q < g.ptr[c + 1]; ++q) col.push_back({g.src[q], g.idx[q], c});
    if (c == f) continue;
    w.merged.resize(w.entries.size() + col.size());
    std::merge(w.entries.begin(), w.entries.end(), col.begin(), col.end(), w.merged.begin(), by_src);
    std::swap(w.entries, w.merged);
  }
  int64_t k = S.a_super_ptr[s];
  for (const Entry& e : w.entries) {
    const int32_t t = w.rowpos[e.row];
    if (t < 0 || t >= nr || rows[t] != e.row)
      fail(ErrorCode::Internal, "symbolic structure misses entry (" + std::to_string(e.row) + ", " +
                                    std::to_string(e.col) + ") of the matrix");
    S.a_src[k] = e.src;
    S.a_dst[k++] = S.super_value_ptr[s] + static_cast<int64_t>(e.col - f) * nr + t;
  }
}

}  // namespace

void assembly_map(SymbolicFactor& S, const CscMatrix& A, const HalfGraph& above) {
  const int32_t n = S.n, ns = S.ns;
  S.a_super_ptr.assign(static_cast<size_t>(ns) + 1, 0);
  for (int32_t s = 0; s < ns; ++s) {
    int64_t count = above.ptr[S.super_first_col[s + 1]] - above.ptr[S.super_first_col[s]];
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) count += above.diag[c] >= 0;
    S.a_super_ptr[s + 1] = S.a_super_ptr[s] + count;
  }
  if (S.a_super_ptr[ns] != A.nnz()) fail(ErrorCode::Internal, "assembly map: the half graph does not match the matrix");
  S.a_src.resize(static_cast<size_t>(A.nnz()));
  S.a_dst.resize(static_cast<size_t>(A.nnz()));
  tbb::enumerable_thread_specific<Workspace> ws([n] { return Workspace{HostVector<int32_t>(n, -1), {}, {}, {}}; });
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, ns, 256), [&](const tbb::blocked_range<int32_t>& r) {
    Workspace& w = ws.local();
    for (int32_t s = r.begin(); s < r.end(); ++s) {
      cancel_point(s);
      map_supernode(S, above, s, w);
    }
  });
}

}  // namespace locus
