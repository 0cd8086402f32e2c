// Factor once: the Cholesky factor of a principal submatrix A_II from the
// factor L of A (thesis chapter 5, §5.4–5.5, eqs. 5.10–5.15).
//
// With the global order kept, A_II = L_II L_II^T + L_IB L_IB^T (eq. 5.14): the
// factor L' of A_II is L_II plus a low-rank update, and it fits in the
// structure of L restricted to I (§5.5). A column j of L' differs from L_II's
// column j only if row j of L has an entry in a column of B = complement(I) or
// an entry in a column of I that differs; so the changed columns are the
// ancestors, in the elimination tree of the restricted structure, of the first
// I-row of every column of L_IB (Figure 5.5c–e). The update therefore
//   1. restricts every supernode of L to its columns and rows in I (empty ones
//      are dropped) — a closed supernodal structure that holds L';
//   2. marks the restricted supernodes reached from those first rows;
//   3. copies the unmarked supernodes' values from L (or, given L by shared
//      pointer, borrows those blocks that are whole global blocks) and
//      recomputes the marked ones with the left-looking factorization
//      (factorize_supernodes).
// The result is an ordinary NumericFactor of A_II: every solve works on it, and
// it can itself be updated for a subset of I (cascading updates, §5.8).
//
// Numbering. Let v_0 < v_1 < ... < v_{m-1} be the vertex set I sorted. Local
// index a of the submatrix is vertex v_a: A_II(a, b) = A(v_a, v_b), and
// `vertices[a] = v_a`. The factor's perm/iperm map factor columns to local
// indices. Its elimination order is L's order restricted to I, except that the
// restricted supernodes are put in postorder of their tree when they are not
// already (the factorization needs subtrees to be contiguous); a postorder of
// the elimination tree is an equivalent ordering: it changes neither the
// structure nor the values of the factor, only their positions.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

struct FactorUpdateOptions {
  // Optional names of A's indices (size n) used in error messages, e.g. the
  // original mesh vertex ids when A is itself a submatrix (cascades). Empty:
  // A's own indices are the names.
  std::span<const int32_t> vertex_ids;
  // Prepared updater with two threads: a result of at least this many bytes
  // has its fresh pages first touched by the second thread while the first one
  // finishes the structure (a fresh mapping faults on every page; see
  // docs/factor_update.md). Smaller results usually reuse heap memory that is
  // already mapped. 0: always (tests).
  int64_t prefault_min_bytes = int64_t{32} << 20;
  // Also extract A_II (FactorUpdate::A_sub, and the result's assembly map).
  // Needed to update the result again (a cascade's next updater) or to
  // refactorize it; the factor itself does not need it: the prepared updater
  // assembles the recomputed supernodes straight from A. false: A_sub stays
  // empty (prepared updater only; the one-shot update always extracts it).
  bool submatrix = true;
  // A set scattered over the mesh (thesis Fig. 5.11) keeps only a small share
  // of the columns of the global supernodes it touches; its restricted
  // structure then holds far more fill than the factor of A_II needs, and the
  // update costs more than factoring A_II afresh. Below this share, A_II is
  // extracted, analysed and factored from scratch in L's relative order
  // (FactorUpdateStats::refactored). 0.28 is the measured crossover, well
  // below the shares of BFS patches: see docs/factor_update.md. 0: never.
  double refactor_below_share = 0.28;
};

struct FactorUpdateStats {
  int32_t n = 0;                      // size of A
  int32_t n_sub = 0;                  // |I|
  int32_t supernodes = 0;             // restricted supernodes (non-empty)
  int32_t supernodes_recomputed = 0;  // marked supernodes
  int32_t columns_marked = 0;         // columns reached by the etree walk (exact, column level)
  int32_t columns_recomputed = 0;     // columns of the marked supernodes (the work done)
  double columns_updated_fraction = 0;  // columns_recomputed / n_sub
  int64_t values_stored = 0;          // doubles in the factor's value array
  int64_t values_recomputed = 0;      // of which in marked supernodes
  int64_t values_borrowed = 0;        // of which read from L's blocks, not stored (sharing updater)
  int64_t nnz_stored = 0;             // entries of the restricted structure (SymbolicFactor::nnz_L)
  int64_t flops_recomputed = 0;       // SymbolicFactor::flops(s) summed over the marked supernodes
  bool reordered = false;             // restricted supernodes needed a postorder
  bool copied_whole = false;          // I = all indices: L copied, nothing recomputed
  bool refactored = false;            // scattered set: A_II factored from scratch (refactor_below_share)
  double touched_share = 0;           // |I| / columns of the global supernodes holding I's columns
  double structure_s = 0, mark_s = 0, copy_s = 0, factor_s = 0;  // phase timings (seconds)
  double assemble_s = 0;  // of structure_s: A_II's extraction (prepared updater: beside marking, copying, factoring)
};

struct FactorUpdate {
  NumericFactor factor;            // factor of A_II, local numbering (see above)
  CscMatrix A_sub;                 // A_II, lower CSC, local numbering
  std::vector<int32_t> vertices;   // local index -> index of A (sorted I)
  FactorUpdateStats stats;
};

// Updates of one factor L of A, for many vertex sets. The constructor checks
// A against L once (sizes, pattern hash: O(nnz(A))); update(I) then costs what
// I and the columns it touches cost, not O(n): its maps of size n are kept and
// reset entry by entry after each call. L (unless shared), A and opt.vertex_ids
// must outlive the updater. One updater serves one thread at a time (its maps are shared
// between calls); use one per thread for concurrent updates.
class FactorUpdater {
 public:
  // Sharing form: the result borrows every block it has unchanged from L
  // (NumericFactor::borrowed) instead of copying it, and holds L (hence its
  // storage) alive through NumericFactor::lender. Same values as the copying
  // form, bit for bit; it allocates and writes only the recomputed and the
  // restricted blocks (a fraction of the result on patches: see
  // docs/factor_update.md).
  FactorUpdater(std::shared_ptr<const NumericFactor> L, const CscMatrix& A, const FactorUpdateOptions& opt = {},
                bool index_rows = true);
  // index_rows: prepare for many updates (O(nnz(A) + structure of L), once):
  // the row -> supernode index that makes marking cost depend on I, and a copy
  // of A in L's column order, from which A_II and its assembly map are read
  // with the locality of the factor (a patch is a few contiguous subtrees)
  // instead of gathering I's columns all over A. A's values are then copied
  // here, once: later changes to A are not seen. Without it each update scans
  // L's rows and gathers A_II from A, which is cheaper for a single update
  // (update_factor uses false).
  FactorUpdater(const NumericFactor& L, const CscMatrix& A, const FactorUpdateOptions& opt = {},
                bool index_rows = true);
  // Factor of A_II. I: indices of A in any order. Throws Error(BadUsage) for an
  // empty I, an index out of range or a repeated index, and Error(Numerical)
  // naming the vertex (A's index, or vertex_ids of it) when A_II is not positive
  // definite. Deterministic for any thread count.
  FactorUpdate update(std::span<const int32_t> I, const RunContext& ctx = {});

 private:
  // One call of update(): its state and steps (plan, restrict, mark, copy or
  // borrow, refactor the marked supernodes; or the whole copy, or the fresh
  // factorization of a scattered set), in kernels/src/update/factor_update_call.hpp.
  struct Call;
  // two_threads: inside an arena of >= 2 threads, with the prepared updater
  // (the structure passes may then run side by side).
  FactorUpdate update_impl(std::span<const int32_t> I, const RunContext& ctx, bool two_threads);

  const NumericFactor& L_;
  std::shared_ptr<const NumericFactor> lender_;  // sharing form only
  const CscMatrix& A_;
  FactorUpdateOptions opt_;
  std::vector<int32_t> local_;    // n: position of a vertex in sorted I, -1 outside (between calls: all -1)
  std::vector<int32_t> col_new_;  // n: restricted column of a factor column, -1 outside (between calls: all -1)
  std::vector<int32_t> in_super_;  // ns: columns of I in each global supernode (between calls: all 0)
  std::vector<int64_t> below_ptr_;   // n + 1: per factor row, the supernodes holding it below their diagonal
  std::vector<int32_t> below_super_;
  std::vector<uint64_t> vbits_, cbits_;  // n bits: I's vertices / factor columns, to sort I in O(m + n/64) (between calls: 0)
  std::vector<int32_t> vrank_;           // n/64: set bits of vbits_ before each word (local index by rank)
  // A in factor numbering, lower (index_rows only): column c holds rows r >= c
  // with their values; entry (r, c) is A(perm[r], perm[c]).
  std::vector<int64_t> ap_ptr_;
  std::vector<int32_t> ap_row_;
  std::vector<double> ap_val_;
};

// One-shot form: FactorUpdater(L, A, opt).update(I, ctx).
FactorUpdate update_factor(const NumericFactor& L, const CscMatrix& A, std::span<const int32_t> I,
                           const RunContext& ctx = {}, const FactorUpdateOptions& opt = {});

// A_II of a lower-stored symmetric A for sorted unique indices `vertices`
// (local index a = vertices[a]); O(sum of the selected columns' lengths + n).
CscMatrix principal_submatrix(const CscMatrix& A, std::span<const int32_t> vertices);

// The elimination order of a symbolic factor as an Ordering (perm/iperm), e.g.
// to analyze A_II from scratch in the order the update produced.
Ordering factor_ordering(const SymbolicFactor& S);

}  // namespace locus
