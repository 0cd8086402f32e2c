// Numeric supernodal Cholesky factorization A = L L^T (DESIGN.md "Numeric core" 3, 4).
//
// Left-looking, supernode by supernode: gather the updates of descendant
// supernodes with BLAS-3 (dsyrk/dgemm), then dpotrf on the diagonal block and
// dtrsm below it. Independent subtrees of the supernodal etree run in parallel
// on oneTBB with single-threaded BLAS inside tasks. The order in which updates
// are summed is fixed, so the factor is bit-identical for any thread count.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "locus/core/default_init_allocator.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct NumericFactor {
  std::shared_ptr<const SymbolicFactor> symbolic;
  // super_value_ptr[ns] entries: supernode blocks, column-major (the strict upper
  // triangle of each diagonal block is unused).
  std::vector<double, DefaultInitAllocator<double>> values;

  // Borrowed blocks (factor-once results, kernels/include/locus/kernels/update/factor_update.hpp): most
  // supernodes of a submesh factor equal a supernode of the factor it was
  // derived from, and are read from there instead of being copied. Then
  // `borrowed` has ns entries (a borrowed block's address, or null), the own
  // blocks are packed in `values` at own_offset[s], and `lender` keeps the
  // borrowed storage alive. Empty for every other factor. Read blocks through
  // block(s): values.data() + super_value_ptr[s] is only right when !borrows().
  std::vector<const double*> borrowed;
  std::vector<int64_t> own_offset;
  std::shared_ptr<const void> lender;

  int32_t n() const { return symbolic ? symbolic->n : 0; }
  bool borrows() const { return !borrowed.empty(); }
  const double* block(int32_t s) const {
    if (borrowed.empty()) return values.data() + symbolic->super_value_ptr[s];
    return borrowed[s] ? borrowed[s] : values.data() + own_offset[s];
  }
  // Writable blocks are own blocks (a borrowed one belongs to the lender).
  double* block(int32_t s) {
    return values.data() + (borrowed.empty() ? symbolic->super_value_ptr[s] : own_offset[s]);
  }
};

// True when f's storage matches its symbolic factor: every block in `values`
// at super_value_ptr, or, for a factor that borrows, both tables sized to the
// supernodes and every own block inside `values`.
bool storage_matches_symbolic(const NumericFactor& f);

// Factors A (lower CSC, original numbering, same pattern that `symbolic` was built from).
// A non-positive pivot raises Error(Numerical) naming the factor column and the
// original (input) index of that column: "not positive definite at vertex 513 (column 20771)";
// Error::where() carries both numbers.
NumericFactor factorize(std::shared_ptr<const SymbolicFactor> symbolic, const CscMatrix& lower,
                        const RunContext& ctx = {});
// Same pattern, new values: reuses the symbolic factor and the storage of f.
void refactorize(NumericFactor& f, const CscMatrix& lower, const RunContext& ctx = {});
// Recomputes only the supernodes s with refactor[s] != 0 (from A and the
// current values of their descendants); the others keep the values f already
// holds, e.g. copied from another factor (chapter 5, factor once). f.values
// must be sized to the symbolic factor. Like every numeric kernel it relies on
// the symbolic invariants (validate_symbolic): supernodes postordered (each
// parent after its children, every subtree a contiguous range), which is what
// lets the subtree tasks run independently; a structure assembled by hand
// (complete_symbolic) must keep that order.
void factorize_supernodes(NumericFactor& f, const CscMatrix& lower, std::span<const uint8_t> refactor,
                          const RunContext& ctx = {});
// Fills columns [c0, c1) of supernode s's block (zeroed, column-major, ld
// nrows(s); `block` points at its column 0) with the entries of A that the
// symbolic factor's assembly map would place there; rowmap[r] is the position
// of factor row r in s. May be called from several threads at once.
using SupernodeAssembler = std::function<void(int32_t s, int32_t c0, int32_t c1, double* block, const int32_t* rowmap)>;
// factorize_supernodes with A's entries supplied by `assemble` instead of a
// matrix and the symbolic factor's assembly map: the factor-once update
// assembles the recomputed supernodes from its own copy of A while it builds
// A_II beside them. The arithmetic is the same as factorize_supernodes' for
// the same entries.
void factorize_supernodes_assembled(NumericFactor& f, std::span<const uint8_t> refactor,
                                    const SupernodeAssembler& assemble, const RunContext& ctx = {});

}  // namespace locus
