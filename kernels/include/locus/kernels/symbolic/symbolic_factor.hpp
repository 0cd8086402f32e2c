// Symbolic Cholesky analysis (thesis §4.2, §5.3; DESIGN.md "Numeric core" 2).
//
// From the pattern of A (lower CSC, original numbering) and an ordering P, builds
// everything numeric factorization and the local solves need, in O(nnz(L)):
// column elimination tree, postorder, column counts (Gilbert–Ng–Peyton),
// fundamental supernodes with relaxed amalgamation, the supernodal etree, the
// supernodes' row structures, and the map from A's entries to L's storage.
//
// Everything is in the *factor* numbering (column k of L = original index
// perm[k]); supernodes are postordered so that every subtree is a contiguous range.
// The structure is immutable and shared by every numeric factor with the same
// pattern (all heat operators M - tL of one mesh, whatever t).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "locus/core/host_allocator.hpp"

#include "locus/kernels/order/ordering.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct SymbolicOptions {
  // Relaxed amalgamation (CHOLMOD-style): merge a child into its parent when the
  // merged supernode has at most `relax_cols_small` columns, or when the fraction
  // of explicit zeros it adds stays below the threshold for its size.
  int32_t relax_cols_small = 4;
  int32_t relax_cols_medium = 16;
  int32_t relax_cols_large = 48;
  double relax_zeros_medium = 0.8;
  double relax_zeros_large = 0.1;
  double relax_zeros_huge = 0.05;
  int32_t max_super_cols = 256;  // never merge beyond this width
};

struct SymbolicFactor {
  int32_t n = 0;
  HostVector<int32_t> perm, iperm;  // see Ordering

  // Column elimination tree of P A P^T (factor numbering); parent = -1 at roots.
  HostVector<int32_t> parent;
  HostVector<int32_t> col_count;    // nnz of each column of L (with diagonal), exact (before amalgamation)
  int64_t nnz_exact = 0;             // sum of col_count
  int32_t etree_height = 0;          // longest leaf-to-root path, in columns

  // Supernodes: columns super_first_col[s] .. super_first_col[s+1]-1.
  int32_t ns = 0;
  HostVector<int32_t> super_first_col;  // ns + 1
  HostVector<int32_t> col_to_super;     // n
  HostVector<int32_t> super_parent;     // ns, -1 at roots; parent > child (postorder)
  HostVector<int64_t> super_row_ptr;    // ns + 1, into super_rows
  HostVector<int32_t> super_rows;       // rows of each supernode, ascending; the first
                                         // ncols(s) are its own columns
  HostVector<int64_t> super_value_ptr;  // ns + 1: block of s = nrows(s) x ncols(s), column-major, ld = nrows(s)
  int64_t nnz_L = 0;                     // stored entries of L (lower trapezoids incl. amalgamation zeros)
  int32_t super_etree_height = 0;

  // Where A's stored entries go in L's values, grouped by supernode so each
  // supernode's task assembles its own block: for k in a_super_ptr[s]..[s+1],
  // L.values[a_dst[k]] = A.values[a_src[k]].
  HostVector<int64_t> a_super_ptr;      // ns + 1
  HostVector<int64_t> a_src, a_dst;     // nnz(A)
  uint64_t a_pattern_hash = 0;           // of A's colptr/rowind: refactorization checks the pattern
  int64_t a_nnz = 0;
  int64_t max_update_entries = 0;        // largest dense update block (workspace size)
  int32_t max_super_rows = 0;            // largest nrows(s) (solve workspace size)

  // Supernodes that update s in a left-looking factorization, ascending
  // (descendants d with a row in s's column range), CSR.
  HostVector<int64_t> update_ptr;       // ns + 1
  HostVector<int32_t> update_from;

  int32_t ncols(int32_t s) const { return super_first_col[s + 1] - super_first_col[s]; }
  int32_t nrows(int32_t s) const { return static_cast<int32_t>(super_row_ptr[s + 1] - super_row_ptr[s]); }
  int64_t flops() const;  // floating-point operations of one numeric factorization
  int64_t flops(int32_t s) const;  // of supernode s alone (its columns' share of flops())
};

// Throws BadInput if A is not square or not lower-stored with sorted rows.
// The cancel flag in ctx is polled between the phases (each O(nnz(A)) or
// O(nnz(L)) of work) and inside the calling thread's loops, and raises
// Error(Cancelled). From 16 384 columns on, the phases run as oneTBB tasks
// on ctx.threads threads (0: the caller's arena), over disjoint subtrees of
// the etree; the result is the same for every thread count.
std::shared_ptr<const SymbolicFactor> analyze(const CscMatrix& lower, const Ordering& ordering,
                                              const SymbolicOptions& opt = {}, const RunContext& ctx = {});

// Fills the derived parts of a symbolic factor whose ordering (n, perm, iperm)
// and supernodal structure (ns, super_first_col, col_to_super, super_parent,
// super_row_ptr, super_rows) are set: value offsets, nnz_L, the assembly map of
// A (lower CSC, original numbering), update lists and workspace sizes, heights;
// and the column etree and counts from the supernodal structure when `parent`
// is empty. analyze() ends with it; the factor-once update (chapter 5) builds
// the restricted structure of a submesh factor and calls it too. The structure
// must be closed: for every supernode d and every supernode s its rows below
// reach, d's rows >= first(s) are rows of s.
void complete_symbolic(SymbolicFactor& S, const CscMatrix& A);

// Recomputes update_ptr/update_from and max_update_entries from the supernodal structure.
void compute_update_lists(SymbolicFactor& S);

// Checks every invariant the numeric kernels index through (permutation,
// supernode ranges, sorted in-range rows, closure of the structure, value
// offsets against num_values (skipped if < 0), assembly map ranges); throws
// Error(BadInput) naming the first violation. For structures read from files.
void validate_symbolic(const SymbolicFactor& S, int64_t num_values);

// Row structure of L in CSR (factor numbering): for each row i, the columns j < i with
// L_ij stored (supernodal pattern), ascending. Chapter 5 (factor-once updates) needs it.
struct RowStructure {
  HostVector<int64_t> row_ptr;  // n + 1
  HostVector<int32_t> cols;
};
RowStructure row_structure(const SymbolicFactor& s);

// Hash of a matrix's sparsity pattern (dimensions, colptr, rowind).
uint64_t pattern_hash(const CscMatrix& A);

}  // namespace locus
