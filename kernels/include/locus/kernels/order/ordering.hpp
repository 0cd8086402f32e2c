// Fill-reducing ordering: METIS nested dissection on the graph of a symmetric
// matrix (thesis §4.2: the etree height it produces decides the cost of local
// solves). Deterministic: METIS runs with a fixed seed and its own random
// generator per call; the result does not depend on the thread count.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/run_context.hpp"
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
//
// Graphs of 4000 vertices or more are split by a METIS vertex separator and
// the two halves ordered at once on two oneTBB threads of the caller's arena
// when ctx.threads allows. Concurrent calls are safe and reproducible: every
// METIS call draws from a generator of its own
// (kernels/include/locus/kernels/order/metis_random.hpp).
// METIS cannot be interrupted: a cancel flag in ctx is checked before METIS
// and between its calls (after the separator, between sequential halves), so
// a cancel returns (Error Cancelled) once the running METIS call ends. No work
// is left running in the background.
Ordering order_matrix(const CscMatrix& lower, const OrderingOptions& opt = {}, const RunContext& ctx = {});

}  // namespace locus
