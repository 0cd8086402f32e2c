// Half adjacency of the permuted matrix (kernels/include/locus/kernels/symbolic/permuted_graph.hpp).
#include "locus/kernels/symbolic/permuted_graph.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

HostVector<int32_t> column_chunks(const CscMatrix& A, int chunks) {
  const int32_t n = A.ncols;
  const int64_t nnz = A.nnz();
  chunks = static_cast<int>(std::clamp<int64_t>(chunks, 1, std::max(1, n)));
  HostVector<int32_t> first(static_cast<size_t>(chunks) + 1, n);
  first[0] = 0;
  for (int c = 1; c < chunks; ++c)  // the column holding entry nnz * c / chunks starts chunk c
    first[c] = static_cast<int32_t>(std::upper_bound(A.colptr.begin(), A.colptr.end(), nnz * c / chunks) -
                                    A.colptr.begin()) - 1;
  return first;
}

void permuted_half_graph(const CscMatrix& A, std::span<const int32_t> pos, Half half, int chunks, HalfGraph& g) {
  const int32_t n = A.ncols;
  const bool below = half == Half::Below;
  const HostVector<int32_t> first = column_chunks(A, chunks);
  chunks = static_cast<int>(first.size()) - 1;
  const auto target = [&](int32_t i, int32_t j) {  // (list, neighbour) of entry (i, j)
    const int32_t a = pos[i], b = pos[j];
    return below ? std::pair{std::max(a, b), std::min(a, b)} : std::pair{std::min(a, b), std::max(a, b)};
  };
  // offset[c * n + k]: entries of chunk c in k's list, then where they start in it.
  HostVector<int32_t> offset(static_cast<size_t>(chunks) * n, 0);
  const auto each_chunk = [&](auto&& body) {
    if (chunks == 1) body(0);
    else tbb::parallel_for(0, chunks, body);
  };
  each_chunk([&](int c) {
    int32_t* cnt = offset.data() + static_cast<size_t>(c) * n;
    for (int32_t j = first[c]; j < first[c + 1]; ++j) {
      cancel_point(j);
      for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p)
        if (A.rowind[p] != j) ++cnt[target(A.rowind[p], j).first];
    }
  });
  g.ptr.assign(static_cast<size_t>(n) + 1, 0);
  chunk_starts(offset.data(), chunks, static_cast<size_t>(n), g.ptr.data());
  g.idx.resize(static_cast<size_t>(g.ptr[n]));
  each_chunk([&](int c) {
    int32_t* next = offset.data() + static_cast<size_t>(c) * n;
    for (int32_t j = first[c]; j < first[c + 1]; ++j) {
      cancel_point(j);
      for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
        const int32_t i = A.rowind[p];
        if (i == j) continue;
        const auto [list, nb] = target(i, j);
        g.idx[g.ptr[list] + next[list]++] = nb;
      }
    }
  });
}

}  // namespace locus
