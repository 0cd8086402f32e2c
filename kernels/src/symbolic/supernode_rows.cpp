// Supernode row structures (kernels/include/locus/kernels/symbolic/supernode_rows.hpp).
#include "locus/kernels/symbolic/supernode_rows.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

struct RowFill {
  SymbolicFactor& S;
  std::span<const int64_t> ptr;
  std::span<const int32_t> idx;
  HostVector<int32_t> child_ptr, children;

  // Rows of s: own columns, then A's rows below, then the children's rows
  // below (`mark` holds the last supernode each row was added to).
  void fill(int32_t s, HostVector<int32_t>& mark) {
    const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
    int32_t* const out = S.super_rows.data() + S.super_row_ptr[s];
    int32_t* const end = S.super_rows.data() + S.super_row_ptr[s + 1];
    int32_t* o = out;
    for (int32_t c = f; c < l; ++c) *o++ = c;
    int32_t* const below = o;
    // Bounds-checked: a count that does not match the rows found is a bug, not a crash.
    const auto add = [&](int32_t r) {
      if (r < l || mark[r] == s) return;
      if (o == end) fail(ErrorCode::Internal, "supernode " + std::to_string(s) + " has more rows than its column count");
      mark[r] = s;
      *o++ = r;
    };
    for (int32_t c = f; c < l; ++c)
      for (int64_t p = ptr[c]; p < ptr[c + 1]; ++p) add(idx[p]);
    for (int32_t q = child_ptr[s]; q < child_ptr[s + 1]; ++q) {
      const int32_t d = children[q];
      for (int64_t p = S.super_row_ptr[d] + S.ncols(d); p < S.super_row_ptr[d + 1]; ++p) add(S.super_rows[p]);
    }
    if (o != end) fail(ErrorCode::Internal, "supernode " + std::to_string(s) + " has fewer rows than its column count");
    std::sort(below, end);
  }
};

}  // namespace

void supernode_rows(SymbolicFactor& S, std::span<const int64_t> ptr, std::span<const int32_t> idx,
                    const SubtreePartition& part) {
  const int32_t n = S.n, ns = S.ns;
  S.super_row_ptr.assign(static_cast<size_t>(ns) + 1, 0);
  for (int32_t s = 0; s < ns; ++s) {
    const int32_t l = S.super_first_col[s + 1];
    S.super_row_ptr[s + 1] = S.super_row_ptr[s] + S.ncols(s) + S.col_count[l - 1] - 1;
  }
  S.super_rows.resize(static_cast<size_t>(S.super_row_ptr[ns]));

  RowFill rf{S, ptr, idx, HostVector<int32_t>(static_cast<size_t>(ns) + 1, 0), HostVector<int32_t>(ns)};
  for (int32_t s = 0; s < ns; ++s)
    if (S.super_parent[s] >= 0) ++rf.child_ptr[S.super_parent[s] + 1];
  for (int32_t s = 0; s < ns; ++s) rf.child_ptr[s + 1] += rf.child_ptr[s];
  {
    HostVector<int32_t> next(rf.child_ptr.begin(), rf.child_ptr.end() - 1);
    for (int32_t s = 0; s < ns; ++s)
      if (S.super_parent[s] >= 0) rf.children[next[S.super_parent[s]]++] = s;
  }
  // One mark array per thread: marks are supernode ids, so none needs a reset.
  tbb::enumerable_thread_specific<HostVector<int32_t>> marks([n] { return HostVector<int32_t>(n, -1); });
  const auto piece = [&](int32_t q) {
    HostVector<int32_t>& mark = marks.local();
    for (int32_t s = part.piece_begin[q]; s < part.piece_end[q]; ++s) {
      cancel_point(s);
      rf.fill(s, mark);
    }
  };
  const int32_t np = part.num_pieces();
  if (np == 1) piece(0);
  else tbb::parallel_for(0, np, piece);
  HostVector<int32_t>& mark = marks.local();
  for (size_t t = 0; t < part.top.size(); ++t) {
    cancel_point(static_cast<int64_t>(t));
    rf.fill(part.top[t], mark);
  }
}

}  // namespace locus
