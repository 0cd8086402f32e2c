// Factor-once update of a supernodal factor to a principal submatrix
// (kernels/include/locus/kernels/update/factor_update.hpp; thesis §5.4–5.5, algorithm steps 1–6 of §5.5).
//
// Supernodal version of the column algorithm of the thesis:
//  - structure: global supernode s restricted to its columns in I is one
//    supernode of L' with rows rows(s) ∩ I. Closure holds because the global
//    structure is closed and restriction keeps every row ≥ first(s') of a
//    descendant inside rows(s) ∩ I. Its supernodal parent is the restricted
//    supernode holding its first off-diagonal row (not the global parent,
//    which may have no column in I).
//  - marking: the column etree of the restricted structure contains every
//    ancestor relation of the exact factor of A_II (its column patterns are
//    supersets), so walking it from the first I-row of each column of L_IB
//    reaches every changed column (§5.5). Per global supernode only one start
//    is needed: the first I-column after its first B-column, or, when its last
//    columns are all in B, its first I-row below — every other start it could
//    give is an ancestor of that one. The walk stops at marked columns.
//  - values: unmarked supernodes copy their restricted rows/columns of L (the
//    sharing form borrows instead those that keep all their global rows and
//    columns: their block is L's block); marked ones are recomputed by
//    factorize_supernodes from A_II and their descendants (copied, borrowed or
//    recomputed), BLAS-3, in parallel subtrees.
//
// Cost (prepared updater, the repeated-update case): nothing is O(n) or
// O(nnz(A)) per update except scans of n/64-word bit sets. I is sorted through
// bit sets; A_II and its assembly map are read from a copy of A stored in L's
// column order, where a patch's columns are a few contiguous ranges (nested
// dissection keeps subtrees together), not gathered from I's columns spread
// over A; the symbolic parts are derived in single passes over the restricted
// structure. A_II's extraction runs beside marking, copying and the
// recomputation, which assembles its supernodes from the same copy of A. With
// two threads the structure passes that handle many rows (restriction, the
// postorder's row remapping, the update lists) are also split in two, each
// half writing its own range, so the result is the same for any thread count;
// the second thread first-touches a large result's fresh pages while the first
// finishes the structure, and takes over part of the copy once A_II is done.
//
// This file holds the updater (its checks and prepared indexes) and one call's
// plan and order of steps; the steps live in update_restriction.cpp,
// update_marking.cpp, update_copy.cpp and partial_refactorization.cpp, over the
// state in factor_update_call.hpp.
#include "locus/kernels/update/factor_update.hpp"

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <string>

#include "factor_update_call.hpp"
#include "locus/core/bit_set.hpp"
#include "locus/error.hpp"
#include "submatrix_extraction.hpp"

namespace locus {

using update_detail::assemble_from_factor_order;
using update_detail::in_arena;
using update_detail::NotFiniteEntry;
using update_detail::seconds_since;

Ordering factor_ordering(const SymbolicFactor& S) { return Ordering{std::vector<int32_t>(S.perm), std::vector<int32_t>(S.iperm)}; }

namespace {
const NumericFactor& factor_of(const std::shared_ptr<const NumericFactor>& L) {
  if (!L) fail(ErrorCode::BadUsage, "update_factor: no factor (null pointer)");
  return *L;
}
}  // namespace

FactorUpdater::FactorUpdater(std::shared_ptr<const NumericFactor> L, const CscMatrix& A,
                             const FactorUpdateOptions& opt, bool index_rows)
    : FactorUpdater(factor_of(L), A, opt, index_rows) {
  lender_ = std::move(L);
}

FactorUpdater::FactorUpdater(const NumericFactor& L, const CscMatrix& A, const FactorUpdateOptions& opt,
                             bool index_rows)
    : L_(L), A_(A), opt_(opt) {
  if (!L.symbolic) fail(ErrorCode::BadUsage, "update_factor: factor has no symbolic part");
  const SymbolicFactor& S = *L.symbolic;
  const int32_t n = S.n;
  if (A.ncols != n || A.nrows != n || A.nnz() != S.a_nnz || pattern_hash(A) != S.a_pattern_hash)
    fail(ErrorCode::BadUsage, "update_factor: matrix does not have the sparsity pattern the factor was built for");
  if (!storage_matches_symbolic(L))
    fail(ErrorCode::BadUsage, "update_factor: factor values are not sized to its symbolic factor");
  if (!opt.vertex_ids.empty() && static_cast<int32_t>(opt.vertex_ids.size()) != n)
    fail(ErrorCode::BadUsage, "update_factor: vertex_ids has " + std::to_string(opt.vertex_ids.size()) +
                                  " entries for a matrix of " + std::to_string(n) + " columns");
  local_.assign(n, -1);
  col_new_.assign(n, -1);
  in_super_.assign(S.ns, 0);
  vbits_.assign((static_cast<size_t>(n) + 63) / 64, 0);
  vrank_.assign(vbits_.size(), 0);
  cbits_.assign(vbits_.size(), 0);
  if (!index_rows) return;
  // A in factor numbering, lower: each entry goes to column min(iperm) (counting sort).
  ap_ptr_.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) ++ap_ptr_[std::min(S.iperm[A.rowind[p]], S.iperm[j]) + 1];
  for (int32_t c = 0; c < n; ++c) ap_ptr_[c + 1] += ap_ptr_[c];
  ap_row_.resize(static_cast<size_t>(ap_ptr_[n]));
  ap_val_.resize(static_cast<size_t>(ap_ptr_[n]));
  {
    std::vector<int64_t> next(ap_ptr_.begin(), ap_ptr_.end() - 1);
    for (int32_t j = 0; j < n; ++j)
      for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
        const int32_t a = S.iperm[A.rowind[p]], b = S.iperm[j];
        const int64_t q = next[std::min(a, b)]++;
        ap_row_[q] = std::max(a, b);
        ap_val_[q] = A.values[p];
      }
  }
  // Row -> supernodes holding it below their diagonal block (the transpose of
  // the supernodal row structure), for marking from the I side.
  below_ptr_.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t d = 0; d < S.ns; ++d)
    for (int64_t t = S.super_row_ptr[d] + S.ncols(d); t < S.super_row_ptr[d + 1]; ++t) ++below_ptr_[S.super_rows[t] + 1];
  for (int32_t r = 0; r < n; ++r) below_ptr_[r + 1] += below_ptr_[r];
  below_super_.resize(static_cast<size_t>(below_ptr_[n]));
  std::vector<int64_t> next(below_ptr_.begin(), below_ptr_.end() - 1);
  for (int32_t d = 0; d < S.ns; ++d)
    for (int64_t t = S.super_row_ptr[d] + S.ncols(d); t < S.super_row_ptr[d + 1]; ++t) below_super_[next[S.super_rows[t]]++] = d;
}

FactorUpdate update_factor(const NumericFactor& L, const CscMatrix& A, std::span<const int32_t> I,
                           const RunContext& ctx, const FactorUpdateOptions& opt) {
  return FactorUpdater(L, A, opt, /*index_rows=*/false).update(I, ctx);
}

FactorUpdate FactorUpdater::update(std::span<const int32_t> I, const RunContext& ctx) {
  // With the prepared updater and two or more threads the structure phase
  // splits its passes too: run the whole update in the arena once instead of
  // entering it for every parallel step.
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  try {
    if (threads < 2 || ap_ptr_.empty()) return update_impl(I, ctx, false);
    FactorUpdate out;
    run_with_threads(threads, [&] { out = update_impl(I, ctx, true); });
    return out;
  } catch (const NotFiniteEntry& e) {
    throw Error(e);  // callers see the library's one exception type
  }
}

FactorUpdater::Call::~Call() {
  const int32_t n = static_cast<int32_t>(u.local_.size());
  for (const int32_t v : I)
    if (v >= 0 && v < n) {
      if (!prepared) u.local_[v] = -1;  // only the one-shot path fills the map
      u.vbits_[static_cast<size_t>(v) >> 6] = 0;
      if (!cbits_clear) u.cbits_[static_cast<size_t>(S.iperm[v]) >> 6] = 0;
    }
  if (maps_filled)
    for (const int32_t c : gcol) {
      u.col_new_[c] = -1;
      u.in_super_[S.col_to_super[c]] = 0;
    }
}

FactorUpdate FactorUpdater::update_impl(std::span<const int32_t> I, const RunContext& ctx, bool two_threads) {
  if (I.empty()) fail(ErrorCode::BadUsage, "update_factor: the vertex set is empty");
  Call call(*this, I, ctx, two_threads);
  call.plan();
  if (call.m == L_.symbolic->n) {
    call.copy_whole();
  } else {
    call.list_factor_columns();
    if (call.st.touched_share < opt_.refactor_below_share) {
      call.refactor_fresh();
    } else {
      call.restrict_to_set();
      if (call.prepared) call.finish_prepared();
      else call.finish_one_shot();
    }
  }
  return std::move(call.out);
}

// Checks I and sorts it, with its factor columns, through bit sets: O(m + n/64).
void FactorUpdater::Call::plan() {
  const int32_t n = S.n;
  auto name = [&](int32_t v) { return std::to_string(opt.vertex_ids.empty() ? v : opt.vertex_ids[v]); };
  for (size_t a = 0; a < I.size(); ++a) {
    const int32_t v = I[a];
    if (v < 0 || v >= n)
      fail(ErrorCode::BadUsage, "update_factor: vertex " + std::to_string(v) + " (entry " + std::to_string(a) +
                                    ") is out of range [0, " + std::to_string(n) + ")");
    uint64_t& w = u.vbits_[static_cast<size_t>(v) >> 6];
    const uint64_t bit = uint64_t{1} << (v & 63);
    if (w & bit) fail(ErrorCode::BadUsage, "update_factor: vertex " + name(v) + " appears twice in the set");
    w |= bit;
  }
  m = static_cast<int32_t>(I.size());
  out.vertices.reserve(m);
  append_set_bits(u.vbits_, out.vertices);
  // Factor columns from the sorted vertices: iperm is then read in ascending
  // order (prefetchable) instead of in I's order (a cache miss per vertex).
  for (const int32_t v : out.vertices) u.cbits_[static_cast<size_t>(S.iperm[v]) >> 6] |= uint64_t{1} << (S.iperm[v] & 63);
  for (size_t wi = 0, r = 0; wi < u.vbits_.size(); ++wi) {  // the rank table of local_of
    u.vrank_[wi] = static_cast<int32_t>(r);
    r += static_cast<size_t>(std::popcount(u.vbits_[wi]));
  }
  if (!prepared)
    for (int32_t a = 0; a < m; ++a) u.local_[out.vertices[a]] = a;
  st.n = n;
  st.n_sub = m;
}

// I = all indices: nothing is removed, L is the factor (same numbering).
void FactorUpdater::Call::copy_whole() {
  out.A_sub = u.A_;
  st.supernodes = S.ns;
  st.values_stored = S.super_value_ptr[S.ns];
  if (borrow) {  // every block is borrowed
    out.factor.symbolic = L.symbolic;
    out.factor.borrowed.resize(S.ns);
    for (int32_t s = 0; s < S.ns; ++s) out.factor.borrowed[s] = L.block(s);
    out.factor.own_offset.assign(S.ns, -1);
    out.factor.lender = u.lender_;
    st.values_borrowed = st.values_stored;
  } else {
    out.factor = L;  // (with its borrowed blocks and their lender, if L borrows)
  }
  st.nnz_stored = S.nnz_L;
  st.copied_whole = true;
  st.copy_s = seconds_since(t0);
}

// I's factor columns, ascending (gcol), and the share of the columns of the
// global supernodes holding them that I keeps (which chooses the fresh path).
void FactorUpdater::Call::list_factor_columns() {
  gcol.reserve(m);
  append_set_bits(u.cbits_, gcol);
  for (const int32_t c : gcol) u.cbits_[static_cast<size_t>(c) >> 6] = 0;
  cbits_clear = true;
  int64_t touched = 0;  // columns of the global supernodes that hold I's columns
  for (int32_t c = 0, prev = -1; c < m; ++c) {
    const int32_t s = S.col_to_super[gcol[c]];
    if (s != prev) touched += S.ncols(s);
    prev = s;
  }
  st.touched_share = static_cast<double>(m) / static_cast<double>(touched);
}

// Prepared updater: marking, copying and the recomputation do not read A_II,
// so they run beside its extraction (independent outputs: the result does not
// depend on the threads). The recomputed supernodes are assembled straight
// from the copy of A in factor order (the entries A_II's map would place), so
// that they need not wait for A_II.
void FactorUpdater::Call::finish_prepared() {
  const SupernodeAssembler direct = [this](int32_t s, int32_t c0, int32_t c1, double* block, const int32_t* rowmap) {
    assemble_direct(s, c0, c1, block, rowmap);
  };
  auto mark_copy_factor = [&] {
    mark_and_copy();
    refactor_marked(&direct);
  };
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  if (threads >= 2) {
    in_arena(ctx, [&](int) { tbb::parallel_invoke([&] { extract_submatrix(); }, mark_copy_factor); });
  } else {
    mark_copy_factor();
    extract_submatrix();
  }
}

// One-shot updater: A_II was gathered with the structure.
void FactorUpdater::Call::finish_one_shot() {
  mark_and_copy();
  ctx.check_cancel();
  refactor_marked(nullptr);
}

// (2) marking, then (3) each unmarked supernode copied from L or borrowed.
void FactorUpdater::Call::mark_and_copy() {
  const auto t1 = clock::now();
  mark_changed();
  count_marked();
  out.factor.symbolic = Sp;
  if (borrow) lay_out_borrowed();
  st.mark_s = seconds_since(t1);
  ctx.check_cancel();
  const auto t2 = clock::now();
  copy_unmarked();
  st.copy_s = seconds_since(t2);
}

// Prepared updater: A_II and its assembly map (FactorUpdateOptions::submatrix).
void FactorUpdater::Call::extract_submatrix() {
  if (!opt.submatrix) return;
  const auto ta = clock::now();
  assemble_from_factor_order(*Sp, R.gcol, u.col_new_, u.ap_ptr_, u.ap_row_, u.ap_val_, out.vertices, opt.vertex_ids,
                             out.A_sub);
  st.assemble_s = seconds_since(ta);
  st.structure_s += st.assemble_s;
}

}  // namespace locus
