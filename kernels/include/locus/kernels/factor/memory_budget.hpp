// Memory budget of a numeric factorization.
//
// A mesh whose factor does not fit in memory must be refused up front with an
// estimate, not killed by the OS half-way through. The symbolic analysis knows
// the exact storage of L before any numeric work, so the estimate is nearly
// exact: L's values (supernodal blocks, padding included), the factorizer's
// per-thread workspace and bookkeeping, and the buffers of one 8-lane solve.
// It does not count the matrix A or the symbolic factor: those already exist
// when the check runs.
#pragma once
#include <cstddef>
#include <cstdint>

#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/run_context.hpp"

namespace locus {

// Physical memory this process may use, in bytes: sysconf's physical pages,
// lowered to the cgroup v2 limit (memory.max) when one is set. 0 if unknown.
std::size_t physical_memory_bytes();

// The limit a RunContext asks for: max_memory_bytes, or 80% of physical
// memory when it is 0 (or unlimited when physical memory is unknown).
std::size_t memory_limit_bytes(const RunContext& ctx);

struct FactorMemoryEstimate {
  int64_t values_bytes = 0;     // super_value_ptr[ns] x 8: nnz_L plus the unused upper triangles of the diagonal blocks
  int64_t workspace_bytes = 0;  // per thread: row map (n int32) + largest dense update block; plus task bookkeeping
  int64_t solve_bytes = 0;      // one 8-lane full solve: (n + max_super_rows) x 8 doubles
  int64_t total_bytes = 0;
  int threads = 1;              // workspace copies counted
};

// Bytes a numeric factorization of S with `threads` workers (>= 1) allocates,
// and then one 8-lane solve with the result.
FactorMemoryEstimate estimate_factor_memory(const SymbolicFactor& S, int threads);

// Throws Error(ResourceLimit) when the estimate for S under ctx's thread
// budget exceeds memory_limit_bytes(ctx); the message gives the estimate in
// GiB, nnz(L), the limit and how to raise it (--max-memory).
void check_factor_memory(const SymbolicFactor& S, const RunContext& ctx);

}  // namespace locus
