// Half of the symmetric adjacency of P A P^T (thesis §4.2), the input of the
// symbolic analysis: for each new index k its neighbours below k (Below: what
// the etree needs) or above k (Above: what the column counts and the
// supernode row structures need). Half the entries of the full graph, so half
// the work to build.
//
// Built by a scatter over A's entries in their order, which keeps each k's
// neighbours in ascending entry order. The entries are split into `chunks`
// consecutive ranges scattered as parallel oneTBB tasks (caller's arena):
// each chunk counts its entries per k first, so every chunk knows where its
// part of each k's list starts, and the result is the same for every chunk
// count. (Gathering each k's neighbours from A and its transpose instead was
// 5x slower: the ordering scatters A's columns over memory.)
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "locus/core/host_allocator.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct HalfGraph {
  HostVector<int64_t> ptr;  // n + 1
  HostVector<int32_t> idx;  // neighbours of k: idx[ptr[k] .. ptr[k+1])
};

enum class Half { Below, Above };

// A lower CSC with sorted rows (original numbering), pos[i] the new index of
// original i. The diagonal is not among the neighbours. Chunks (>= 1) cost
// chunks * n * 4 bytes of counters; one chunk: no oneTBB algorithm runs.
void permuted_half_graph(const CscMatrix& A, std::span<const int32_t> pos, Half half, int chunks, HalfGraph& g);

// A's columns in `chunks` consecutive ranges of about nnz / chunks entries:
// chunk c is [first[c], first[c+1]); fewer chunks for tiny matrices.
HostVector<int32_t> column_chunks(const CscMatrix& A, int chunks);

// The counting step of a chunked scatter: offset[c * n + k] holds chunk c's
// count for list k on entry and where chunk c's entries start within list k
// on return (chunks in order, so any chunk count gives the same lists);
// ptr[k + 1] = ptr[k] + list k's total.
template <class Count, class Ptr>
void chunk_starts(Count* offset, int chunks, std::size_t n, Ptr* ptr) {
  for (std::size_t k = 0; k < n; ++k) {
    Count run = 0;
    for (int c = 0; c < chunks; ++c) {
      const Count m = offset[static_cast<std::size_t>(c) * n + k];
      offset[static_cast<std::size_t>(c) * n + k] = run;
      run += m;
    }
    ptr[k + 1] = ptr[k] + run;
  }
}

}  // namespace locus
