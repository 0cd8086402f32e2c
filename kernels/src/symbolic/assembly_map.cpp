// Assembly map A -> L (kernels/include/locus/kernels/symbolic/assembly_map.hpp).
#include "locus/kernels/symbolic/assembly_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"
#include "locus/kernels/symbolic/permuted_graph.hpp"

namespace locus {

namespace {

// Positions in L of supernode s's entries, from their factor (row, col).
void place_supernode(SymbolicFactor& S, std::span<const int32_t> entry_row, std::span<const int32_t> entry_col,
                     int32_t s, HostVector<int32_t>& rowpos) {
  const int32_t f = S.super_first_col[s], nr = S.nrows(s);
  const int32_t* rows = S.super_rows.data() + S.super_row_ptr[s];
  for (int32_t t = 0; t < nr; ++t) rowpos[rows[t]] = t;
  for (int64_t k = S.a_super_ptr[s]; k < S.a_super_ptr[s + 1]; ++k) {
    const int32_t r = entry_row[k], c = entry_col[k];
    const int32_t t = rowpos[r];  // stale from another supernode unless r is a row of s
    if (t < 0 || t >= nr || rows[t] != r)
      fail(ErrorCode::Internal, "symbolic structure misses entry (" + std::to_string(r) + ", " + std::to_string(c) +
                                    ") of the matrix");
    S.a_dst[k] = S.super_value_ptr[s] + static_cast<int64_t>(c - f) * nr + t;
  }
}

}  // namespace

void assembly_map(SymbolicFactor& S, const CscMatrix& A, int chunks) {
  const int32_t n = S.n, ns = S.ns;
  const int64_t nnz = A.nnz();
  const HostVector<int32_t> first = column_chunks(A, chunks);
  chunks = static_cast<int>(first.size()) - 1;
  const auto each_chunk = [&](auto&& body) {
    if (chunks == 1) body(0);
    else tbb::parallel_for(0, chunks, body);
  };
  // offset[c * ns + s]: chunk c's entries of supernode s, then where they start in its group.
  HostVector<int64_t> offset(static_cast<size_t>(chunks) * ns, 0);
  each_chunk([&](int c) {
    int64_t* cnt = offset.data() + static_cast<size_t>(c) * ns;
    for (int32_t j = first[c]; j < first[c + 1]; ++j) {
      cancel_point(j);
      const int32_t b = S.iperm[j];
      for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) ++cnt[S.col_to_super[std::min(S.iperm[A.rowind[p]], b)]];
    }
  });
  S.a_super_ptr.assign(static_cast<size_t>(ns) + 1, 0);
  chunk_starts(offset.data(), chunks, static_cast<size_t>(ns), S.a_super_ptr.data());
  S.a_src.resize(static_cast<size_t>(nnz));
  S.a_dst.resize(static_cast<size_t>(nnz));
  HostVector<int32_t> entry_row(static_cast<size_t>(nnz)), entry_col(static_cast<size_t>(nnz));  // by group slot
  each_chunk([&](int c) {
    int64_t* next = offset.data() + static_cast<size_t>(c) * ns;
    for (int32_t j = first[c]; j < first[c + 1]; ++j) {
      cancel_point(j);
      const int32_t b = S.iperm[j];
      for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
        const int32_t a = S.iperm[A.rowind[p]], lo = std::min(a, b);
        const int32_t s = S.col_to_super[lo];
        const int64_t k = S.a_super_ptr[s] + next[s]++;
        S.a_src[k] = p;
        entry_row[k] = std::max(a, b);
        entry_col[k] = lo;
      }
    }
  });
  offset = {};
  tbb::enumerable_thread_specific<HostVector<int32_t>> rowpos([n] { return HostVector<int32_t>(n, -1); });
  const auto range = [&](const tbb::blocked_range<int32_t>& r) {
    HostVector<int32_t>& pos = rowpos.local();
    for (int32_t s = r.begin(); s < r.end(); ++s) {
      cancel_point(s);
      place_supernode(S, entry_row, entry_col, s, pos);
    }
  };
  if (chunks > 1) tbb::parallel_for(tbb::blocked_range<int32_t>(0, ns, 256), range);
  else range(tbb::blocked_range<int32_t>(0, ns));
}

void release_assembly_map(SymbolicFactor& S) {
  // swap with empty vectors: clear() would keep the capacity
  HostVector<int64_t>().swap(S.a_super_ptr);
  HostVector<int64_t>().swap(S.a_src);
  HostVector<int64_t>().swap(S.a_dst);
  HostVector<int64_t>().swap(S.update_ptr);
  HostVector<int32_t>().swap(S.update_from);
  // The column etree and counts: read by the analysis (and the factor cache's
  // writer) only, never by a solve (3.3 MB at 416k columns).
  HostVector<int32_t>().swap(S.parent);
  HostVector<int32_t>().swap(S.col_count);
}

}  // namespace locus
