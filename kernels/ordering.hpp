// Fill-reducing ordering: METIS nested dissection (METIS_NodeND) on the graph
// of a symmetric matrix (thesis §4.2: the etree height it produces decides the
// cost of local solves). Deterministic: METIS runs with a fixed seed.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/sparse_matrix.hpp"

namespace locus {

struct Ordering {
  std::vector<int32_t> perm;   // perm[k]  = original index eliminated k-th
  std::vector<int32_t> iperm;  // iperm[i] = position of original index i
};

struct OrderingOptions {
  enum class Method { Metis, Natural } method = Method::Metis;
  int seed = 7;  // METIS random seed (fixed: same input, same ordering)
};

// Orders the graph of a lower-stored symmetric matrix.
Ordering order_matrix(const CscMatrix& lower, const OrderingOptions& opt = {});

}  // namespace locus
